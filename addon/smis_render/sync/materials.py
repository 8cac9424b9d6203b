"""Blender materials (shader node trees) -> engine material dicts.

The engine has no shader nodes: a material is a flat, weighted list of
closures plus an emission colour. The Surface input of the material's output
node is evaluated here once, on constants only: Mix Shader factors and Add
Shader sums are folded into the closure weights. Only unlinked input values
(`default_value`) are read; textures and other non-shader links are ignored
with a warning, unsupported shader nodes become a neutral diffuse.
"""

from . import nodes
from ..spectral_properties import material_spectral
from .volumes import translate_volume

NEUTRAL_GREY = (0.8, 0.8, 0.8)
BLACK = (0.0, 0.0, 0.0)
DEFAULT_MATERIAL_NAME = "SMIS default grey"


def closure(kind, weight, roughness=0.0, ior=1.5, fresnel="none", f0=BLACK):
    """One engine closure; every key is always present so the engine can be strict."""
    return {"kind": kind, "fresnel": fresnel, "weight": tuple(weight), "f0": tuple(f0),
            "roughness": float(roughness), "ior": float(ior)}


def default_material(name=DEFAULT_MATERIAL_NAME):
    return {"name": name, "closures": [closure("diffuse", NEUTRAL_GREY)], "emission": BLACK}


def _scale(w, s):
    """Colour times a scalar or a colour."""
    if isinstance(s, (int, float)):
        return (w[0] * s, w[1] * s, w[2] * s)
    return (w[0] * s[0], w[1] * s[1], w[2] * s[2])


def _rgb(value):
    return (float(value[0]), float(value[1]), float(value[2]))


def _clamp01(x):
    return min(max(float(x), 0.0), 1.0)


def _is_zero(w):
    return max(w) <= 0.0


class _Translation:
    """State of one material's translation: collected closures, emission, warnings."""

    def __init__(self, material, warn):
        self.material = material
        self.warn = warn
        self.closures = []
        self.emission = BLACK
        self._checked_nodes = set()

    # -- helpers -----------------------------------------------------------------

    def _node_label(self, node):
        return "node '%s' (%s)" % (node.name, node.bl_idname)

    def _warn_node(self, node, text):
        self.warn("Material '%s': %s %s" % (self.material.name, self._node_label(node), text))

    def _check_links(self, node):
        """Warn once per node about linked non-shader inputs, whose values we can't evaluate."""
        if node.name in self._checked_nodes:
            return
        self._checked_nodes.add(node.name)
        linked = nodes.linked_inputs(node)
        if linked:
            self._warn_node(node, "has linked inputs (%s); textures and other node inputs are "
                                  "not supported, using the inputs' own values" % ", ".join(linked))

    def _value(self, node, name):
        value = node.inputs[name].default_value
        return value if isinstance(value, float) else _rgb(value)

    def _add(self, c):
        if not _is_zero(c["weight"]):
            self.closures.append(c)

    def _add_emission(self, e):
        self.emission = tuple(a + b for a, b in zip(self.emission, e))

    def _fallback(self, node, w):
        self._warn_node(node, "is not supported, using a neutral diffuse")
        self._add(closure("diffuse", _scale(w, NEUTRAL_GREY)))

    # -- the walk ----------------------------------------------------------------

    def shader(self, output_socket, w):
        """Add the closures produced by `output_socket`, scaled by the colour weight w."""
        if _is_zero(w):
            return
        node = output_socket.node
        handler = _HANDLERS.get(node.bl_idname)
        if handler is None or output_socket.type != 'SHADER':
            # Also catches a colour/float output plugged into a shader socket.
            self._fallback(node, w)
            return
        self._check_links(node)
        handler(self, node, w)

    def _shader_input(self, socket, w):
        src = nodes.linked_output(socket)
        if src is not None:  # an unlinked shader input contributes nothing (black)
            self.shader(src, w)

    def mix(self, node, w):
        fac = _clamp01(self._value(node, "Fac"))
        self._shader_input(node.inputs[1], _scale(w, 1.0 - fac))
        self._shader_input(node.inputs[2], _scale(w, fac))

    def add(self, node, w):
        self._shader_input(node.inputs[0], w)
        self._shader_input(node.inputs[1], w)

    def diffuse(self, node, w):
        if self._value(node, "Roughness") > 0.0:
            self._warn_node(node, "has Roughness > 0 (Oren-Nayar), which is not supported; "
                                  "using Lambert")
        self._add(closure("diffuse", _scale(w, self._value(node, "Color"))))

    def _roughness(self, node, supported):
        """Roughness of a Glossy/Glass node; other distributions approximated by GGX."""
        if node.distribution == 'SHARP':
            return 0.0
        if node.distribution not in supported:
            self._warn_node(node, "uses the %s distribution, which is not supported; using GGX"
                            % node.distribution)
        return _clamp01(self._value(node, "Roughness"))

    def glossy(self, node, w):
        # Cycles' Glossy BSDF has no Fresnel term: the colour is the reflectance.
        rough = self._roughness(node, {'GGX'})
        self._add(closure("microfacet", _scale(w, self._value(node, "Color")), roughness=rough,
                          fresnel="none"))

    def glass(self, node, w):
        rough = self._roughness(node, {'GGX'})
        self._add(closure("dielectric", _scale(w, self._value(node, "Color")), roughness=rough,
                          ior=self._value(node, "IOR")))

    def emission(self, node, w):
        strength = self._value(node, "Strength")
        self._add_emission(_scale(_scale(w, self._value(node, "Color")), strength))

    def principled(self, node, w):
        # Approximation of Blender 3.4's Principled BSDF by four lobes and emission.
        # With m = metallic and t = transmission * (1 - m):
        #   diffuse                  weight base * (1-m) * (1-t)
        #   dielectric specular      microfacet, dielectric Fresnel, weight (1-m) * (1-t)
        #   metal                    microfacet, Schlick Fresnel with f0 = base, weight m
        #   glass (transmission)     dielectric, weight base * t, roughness and IOR inputs
        #   emission                 Emission colour * Emission Strength
        # The specular lobe's IOR comes from the Specular input, as Cycles 3.4 does
        # (f0 = 0.08 * specular, ior = 2 / (1 - sqrt(f0)) - 1; Specular 0.5 gives 1.5);
        # the IOR input is used by the glass lobe only, as in Cycles 3.4.
        # Ignored (with one warning if not at their neutral values): subsurface, specular
        # tint, anisotropy, sheen, clearcoat, alpha, transmission roughness, multiscatter.
        v = lambda name: self._value(node, name)  # noqa: E731
        base = v("Base Color")
        m = _clamp01(v("Metallic"))
        t = _clamp01(v("Transmission")) * (1.0 - m)
        rough = _clamp01(v("Roughness"))
        specular = max(v("Specular"), 0.0)
        self._warn_principled_extras(node, t)

        dielectric_w = (1.0 - m) * (1.0 - t)
        self._add(closure("diffuse", _scale(w, _scale(base, dielectric_w))))
        f0 = min(0.08 * specular, 0.99)
        if f0 > 0.0:
            spec_ior = 2.0 / (1.0 - f0 ** 0.5) - 1.0
            self._add(closure("microfacet", _scale(w, dielectric_w), roughness=rough,
                              fresnel="dielectric", ior=spec_ior, f0=(f0, f0, f0)))
        self._add(closure("microfacet", _scale(w, m), roughness=rough, fresnel="schlick", f0=base))
        self._add(closure("dielectric", _scale(w, _scale(base, t)), roughness=rough, ior=v("IOR")))
        self._add_emission(_scale(_scale(w, v("Emission")), v("Emission Strength")))

    def _warn_principled_extras(self, node, t):
        v = lambda name: self._value(node, name)  # noqa: E731
        ignored = [name for name in ("Subsurface", "Specular Tint", "Anisotropic", "Sheen",
                                     "Clearcoat") if v(name) > 0.0]
        if v("Alpha") < 1.0:
            ignored.append("Alpha")
        if t > 0.0 and v("Transmission Roughness") > 0.0:
            ignored.append("Transmission Roughness")
        if node.distribution != 'GGX':
            ignored.append("Multiscatter GGX (using GGX)")
        if ignored:
            self._warn_node(node, "uses %s, not supported and ignored" % ", ".join(ignored))


_HANDLERS = {
    'ShaderNodeMixShader': _Translation.mix,
    'ShaderNodeAddShader': _Translation.add,
    'ShaderNodeBsdfDiffuse': _Translation.diffuse,
    'ShaderNodeBsdfGlossy': _Translation.glossy,
    'ShaderNodeBsdfGlass': _Translation.glass,
    'ShaderNodeEmission': _Translation.emission,
    'ShaderNodeBsdfPrincipled': _Translation.principled,
}


def translate(material, warn):
    """Engine material dict for a Blender material. `warn(msg)` receives warnings."""
    name = material.name_full
    if not material.use_nodes or material.node_tree is None:
        # What Cycles renders for a material without nodes.
        return dict({"name": name, "closures": [closure("diffuse", _rgb(material.diffuse_color))],
                     "emission": BLACK}, **material_spectral(material))

    tr = _Translation(material, warn)
    output = nodes.output_node(material.node_tree)
    volume = None
    pass_through = False
    if output is None:
        warn("Material '%s' has no Material Output node for Cycles/All; it renders black"
             % material.name)
    else:
        surface = nodes.linked_output(output.inputs["Surface"])
        volume = translate_volume(output, "Material '%s'" % material.name, warn)
        if surface is not None:
            tr.shader(surface, (1.0, 1.0, 1.0))
        # An unlinked Surface renders black, as in Cycles, unless the material has a volume: then
        # the mesh is only the boundary of the medium and rays pass straight through it.
        pass_through = surface is None and volume is not None
    return dict({"name": name, "closures": tr.closures, "emission": tr.emission, "volume": volume,
                 "pass_through": pass_through}, **material_spectral(material))


class MaterialCache:
    """Adds each Blender material to the engine scene once and remembers its id."""

    def __init__(self, scene, reporter):
        self._scene = scene
        self._reporter = reporter
        self._ids = {}

    def id_for(self, material):
        """Engine material id for a Blender material, or for the default grey if None."""
        key = material.name_full if material is not None else None
        mat_id = self._ids.get(key)
        if mat_id is None:
            mat_id = self._add(material)
            self._ids[key] = mat_id
        return mat_id

    def _add(self, material):
        if material is None:
            return self._scene.add_material(default_material())
        desc = translate(material, self._reporter.warning)
        try:
            return self._scene.add_material(desc)
        except ValueError as exc:
            self._reporter.warning("Material '%s' was refused by the engine (%s); using a "
                                   "neutral diffuse" % (material.name, exc))
            return self._scene.add_material(default_material(desc["name"]))

    def __len__(self):
        return len(self._ids)
