"""Volume shaders (a material's or the world's Volume output) -> a homogeneous medium dict.

Cycles' conventions (kernel/svm/closure.h, 3.4), with w the Mix Shader weight reaching the node:
  Volume Scatter      sigma_s += w * density * colour        (extinction = scattering)
  Volume Absorption   sigma_a += w * density * (1 - colour)
  Principled Volume   sigma_s += w * density * colour,
                      sigma_a += w * density * max(1 - colour, 0) * max(1 - sqrt(absorption colour), 0)
Add Shader sums, Mix Shader blends. Several scattering closures with different anisotropies are
one Henyey-Greenstein lobe in the engine: its g is their sigma_s-weighted mean (with a warning).
Only constant inputs are read (the medium is homogeneous); emission in volumes is not supported.
"""

from . import nodes


def _rgb(value):
    return (float(value[0]), float(value[1]), float(value[2]))


class _Medium:
    def __init__(self, owner, warn):
        self.owner = owner
        self.warn = warn
        self.sigma_a = [0.0, 0.0, 0.0]
        self.sigma_s = [0.0, 0.0, 0.0]
        self.g_weighted = 0.0
        self.g_values = set()

    def _warn_node(self, node, text):
        self.warn("%s: node '%s' (%s) %s" % (self.owner, node.name, node.bl_idname, text))

    def _scatter(self, w, density, color, g):
        for c in range(3):
            self.sigma_s[c] += w * density * max(color[c], 0.0)
        self.g_weighted += w * density * sum(max(x, 0.0) for x in color) * g
        self.g_values.add(round(g, 6))

    def _absorb(self, w, coeff):
        for c in range(3):
            self.sigma_a[c] += w * max(coeff[c], 0.0)

    def shader(self, socket, w):
        if w <= 0.0:
            return
        node = socket.node
        handler = _HANDLERS.get(node.bl_idname)
        if handler is None or socket.type != 'SHADER':
            self._warn_node(node, "is not a supported volume shader; ignored")
            return
        linked = nodes.linked_inputs(node)
        if linked:
            self._warn_node(node, "has linked inputs (%s); only homogeneous media are supported, "
                                  "using the inputs' own values" % ", ".join(linked))
        handler(self, node, w)

    def _input(self, socket, w):
        src = nodes.linked_output(socket)
        if src is not None:
            self.shader(src, w)

    def mix(self, node, w):
        fac = min(max(float(node.inputs["Fac"].default_value), 0.0), 1.0)
        self._input(node.inputs[1], w * (1.0 - fac))
        self._input(node.inputs[2], w * fac)

    def add(self, node, w):
        self._input(node.inputs[0], w)
        self._input(node.inputs[1], w)

    def scatter(self, node, w):
        density = max(float(node.inputs["Density"].default_value), 0.0)
        self._scatter(w, density, _rgb(node.inputs["Color"].default_value),
                      float(node.inputs["Anisotropy"].default_value))

    def absorption(self, node, w):
        density = max(float(node.inputs["Density"].default_value), 0.0)
        color = _rgb(node.inputs["Color"].default_value)
        self._absorb(w, [density * (1.0 - c) for c in color])

    def principled(self, node, w):
        density = max(float(node.inputs["Density"].default_value), 0.0)
        color = _rgb(node.inputs["Color"].default_value)
        absorption_color = _rgb(node.inputs["Absorption Color"].default_value)
        self._scatter(w, density, color, float(node.inputs["Anisotropy"].default_value))
        self._absorb(w, [density * max(1.0 - c, 0.0) * max(1.0 - max(a, 0.0) ** 0.5, 0.0)
                         for c, a in zip(color, absorption_color)])
        emissive = (float(node.inputs["Emission Strength"].default_value) > 0.0
                    or float(node.inputs["Blackbody Intensity"].default_value) > 0.0)
        if emissive:
            self._warn_node(node, "emits light; volume emission is not supported and ignored")

    def result(self):
        total = sum(self.sigma_s)
        if len(self.g_values) > 1:
            self.warn("%s mixes scattering with different anisotropies %s; using their "
                      "scattering-weighted mean" % (self.owner, sorted(self.g_values)))
        g = self.g_weighted / total if total > 0.0 else 0.0
        return {"sigma_a": tuple(self.sigma_a), "sigma_s": tuple(self.sigma_s), "anisotropy": g}


_HANDLERS = {
    'ShaderNodeMixShader': _Medium.mix,
    'ShaderNodeAddShader': _Medium.add,
    'ShaderNodeVolumeScatter': _Medium.scatter,
    'ShaderNodeVolumeAbsorption': _Medium.absorption,
    'ShaderNodeVolumePrincipled': _Medium.principled,
}


def translate_volume(output_node, owner, warn):
    """Medium dict for the Volume input of a material or world output node, or None if unlinked."""
    if output_node is None or "Volume" not in output_node.inputs:
        return None
    src = nodes.linked_output(output_node.inputs["Volume"])
    if src is None:
        return None
    medium = _Medium(owner, warn)
    medium.shader(src, 1.0)
    return medium.result()
