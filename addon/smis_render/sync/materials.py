"""Blender materials (shader node trees) -> engine material dicts.

The engine has no shader nodes: a material is a flat, weighted list of
closures plus an emission colour. The Surface input of the material's output
node is evaluated here once, on constants only: Mix Shader factors and Add
Shader sums are folded into the closure weights. Colour inputs fed by an Image
Texture or Object Info, and Normal inputs fed by a tangent-space Normal Map on an
Image Texture, become per-hit engine inputs (textures.py); other links are
ignored with one warning per node, unsupported shader nodes become a neutral
diffuse.
"""

import bpy

from . import nodes, textures as tex
from ..spectral_properties import material_spectral
from .volumes import translate_volume

NEUTRAL_GREY = (0.8, 0.8, 0.8)
BLACK = (0.0, 0.0, 0.0)
DEFAULT_MATERIAL_NAME = "SMIS default grey"


def closure(kind, weight, roughness=0.0, ior=1.5, fresnel="none", f0=BLACK, **inputs):
    """One engine closure; every key is always present so the engine can be strict.
    `inputs`: texture / object_color / to_f0 (textures.ColorInput.closure_keys)."""
    return {"kind": kind, "fresnel": fresnel, "weight": tuple(weight), "f0": tuple(f0),
            "roughness": float(roughness), "ior": float(ior), **inputs}


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

    def __init__(self, material, warn, textures=None):
        self.material = material
        self.warn = warn
        self.textures = textures
        self.closures = []
        self.emission = BLACK
        self.uv_map = None        # UV map the textures read ('' = active render), None = no UVs
        self.normal_map = None
        self.alpha = None         # {"value": a, "texture": id?} for cut-outs
        self.transparent = BLACK  # summed Transparent BSDF weight (straight-through colour)
        self.emission_texture = None   # engine texture id multiplying the emission
        self._constant_emission = False  # emission added without a texture (see _emit)
        self._checked_nodes = set()
        self._translated_links = set()  # (node name, input name) handled by textures.py

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
        linked = ["%s <- %s" % (name, self._node_label(nodes.linked_output(node.inputs[name]).node))
                  for name in nodes.linked_inputs(node) if (node.name, name) not in self._translated_links]
        if linked:
            self._warn_node(node, "has linked inputs the engine cannot translate (%s); using the "
                                  "inputs' own values" % ", ".join(linked))

    def _color(self, node, name):
        """A colour input as a textures.ColorInput (constant, texture or object colour)."""
        socket = node.inputs[name]
        ci = tex.color_input(socket, self.textures, self._warn_node)
        if ci is None:  # untranslatable link: its own value, and _check_links warns
            return tex.ColorInput(constant=_rgb(socket.default_value))
        if socket.is_linked:
            self._translated_links.add((node.name, name))
        if ci.uv_map is not None:
            self._use_uv_map(ci.uv_map)
        return ci

    def _use_uv_map(self, name):
        if self.uv_map is not None and self.uv_map != name:
            self.warn("Material '%s': textures read different UV maps (%s, %s); using %s for all"
                      % (self.material.name, self.uv_map or "default", name or "default",
                         self.uv_map or "default"))
            return
        self.uv_map = name

    def _normal(self, node):
        """Tangent-space normal map feeding the node's Normal input (one per material)."""
        if "Normal" not in node.inputs:
            return
        found = tex.normal_map(node.inputs["Normal"], self.textures, self._warn_node)
        if found is None or found[0] is None:
            return  # unlinked, or not translatable: _check_links names it
        self._set_per_material(node, "Normal", "normal_map", *found)

    def _alpha(self, node):
        """Principled Alpha: a constant below 1 or an Image Texture's Alpha makes the material a
        stochastic cut-out (one alpha per material)."""
        found = tex.alpha_input(node.inputs["Alpha"], self.textures)
        if found is not None:  # else opaque, or an untranslatable link (_check_links names it)
            self._set_per_material(node, "Alpha", "alpha", *found)

    def _set_per_material(self, node, input_name, attr, desc, uv_map):
        """Record a per-material input (normal map, alpha) translated from node's input; a second,
        different one is warned about and ignored."""
        if node.inputs[input_name].is_linked:
            self._translated_links.add((node.name, input_name))
        current = getattr(self, attr)
        if current is not None and current != desc:
            self._warn_node(node, "has a second, different %s; using the first" % input_name)
            return
        setattr(self, attr, desc)
        if uv_map is not None:
            self._use_uv_map(uv_map)

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
        handler(self, node, w)
        self._normal(node)
        self._check_links(node)

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
        self._add(_colored("diffuse", w, self._color(node, "Color")))

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
        self._add(_colored("microfacet", w, self._color(node, "Color"), roughness=rough,
                           fresnel="none"))

    def glass(self, node, w):
        rough = self._roughness(node, {'GGX'})
        self._add(_colored("dielectric", w, self._color(node, "Color"), roughness=rough,
                           ior=self._value(node, "IOR")))

    def emission(self, node, w):
        self._emit(node, w, "Color", self._value(node, "Strength"))

    def _emit(self, node, w, color_name, strength):
        """Emission of colour input `color_name` times strength; an Image Texture on the colour
        becomes the material's emission texture (one per material), looked up at every hit and at
        every light sample on the emissive triangles."""
        ci = self._color(node, color_name)
        if ci.object_color:
            self._warn_node(node, "has Object Info Color on %s, not supported for emission; "
                                  "using white" % color_name)
        textured = ci.texture is not None
        e = _scale(w, strength) if ci.constant is None else _scale(_scale(w, ci.constant), strength)
        if _is_zero(e):
            return
        if textured and self.emission_texture is None:
            self.emission_texture = ci.texture
        elif textured and self.emission_texture != ci.texture:
            self._warn_node(node, "has a second, different emission texture; using the first")
        self._constant_emission = self._constant_emission or not textured
        if self.emission_texture is not None and self._constant_emission:
            self._warn_node(node, "mixes textured and constant emission; the texture applies to both")
        self._add_emission(e)

    def transparent(self, node, w):
        # Cycles' Transparent BSDF: light passes straight through, tinted by Color. The material
        # turns the grey part of the summed tint into a stochastic cut-out (free, as with Alpha) and
        # the coloured rest into a straight-through Dirac lobe (see translate()).
        color = self._color(node, "Color")
        if color.constant is None:
            self._warn_node(node, "has a linked Color, not supported on Transparent BSDF; using white")
            color = tex.ColorInput(constant=(1.0, 1.0, 1.0))
        self.transparent = tuple(a + b for a, b in zip(self.transparent, _scale(w, color.constant)))

    def principled(self, node, w):
        # Approximation of Blender 3.4's Principled BSDF by four lobes and emission.
        # With m = metallic and t = transmission * (1 - m):
        #   diffuse                  weight base * (1-m) * (1-t), Cycles' principled diffuse
        #                            (Burley's retro-reflection driven by Roughness)
        #   dielectric specular      microfacet, dielectric Fresnel, weight (1-m) * (1-t)
        #   metal                    microfacet, Schlick Fresnel with f0 = base, weight m
        #   glass (transmission)     dielectric, weight base * t, roughness and IOR inputs
        #   emission                 Emission colour * Emission Strength
        # The specular lobe's IOR comes from the Specular input, as Cycles 3.4 does
        # (f0 = 0.08 * specular, ior = 2 / (1 - sqrt(f0)) - 1; Specular 0.5 gives 1.5);
        # the IOR input is used by the glass lobe only, as in Cycles 3.4.
        #   sheen, clearcoat         Cycles' principled sheen and clearcoat lobes (_sheen, _clearcoat)
        # Ignored (with one warning if not at their neutral values): subsurface, specular
        # tint, anisotropy, transmission roughness, multiscatter.
        v = lambda name: self._value(node, name)  # noqa: E731
        base_in = self._color(node, "Base Color")
        m = _clamp01(v("Metallic"))
        t = _clamp01(v("Transmission")) * (1.0 - m)
        rough = _clamp01(v("Roughness"))
        specular = max(v("Specular"), 0.0)
        self._warn_principled_extras(node, t)
        self._alpha(node)

        dielectric_w = (1.0 - m) * (1.0 - t)
        self._add(_colored("principled_diffuse", _scale(w, dielectric_w), base_in, roughness=rough))
        f0 = min(0.08 * specular, 0.99)
        if f0 > 0.0:
            spec_ior = 2.0 / (1.0 - f0 ** 0.5) - 1.0
            self._add(closure("microfacet", _scale(w, dielectric_w), roughness=rough,
                              fresnel="dielectric", ior=spec_ior, f0=(f0, f0, f0)))
        self._add(closure("microfacet", _scale(w, m), roughness=rough, fresnel="schlick",
                          f0=base_in.constant or (1.0, 1.0, 1.0), **base_in.closure_keys(to_f0=True)))
        self._add(_colored("dielectric", _scale(w, t), base_in, roughness=rough, ior=v("IOR")))
        self._sheen(node, _scale(w, dielectric_w), base_in)
        self._clearcoat(node, w)
        self._emit(node, w, "Emission", v("Emission Strength"))

    def _sheen(self, node, w, base_in):
        # Cycles 3.4: weight Sheen x (1 - metallic)(1 - transmission) x a colour mixed from white to
        # the base colour's tint (base / luminance) by Sheen Tint; the lobe is LobeKind::Sheen.
        sheen = max(self._value(node, "Sheen"), 0.0)
        if sheen <= 0.0:
            return
        tint = _clamp01(self._value(node, "Sheen Tint"))
        base = base_in.constant
        if base is None:
            if tint > 0.0:
                self._warn_node(node, "has Sheen Tint with a linked Base Color; the sheen is untinted")
            base, tint = (1.0, 1.0, 1.0), 0.0
        lum = 0.2126 * base[0] + 0.7152 * base[1] + 0.0722 * base[2]  # Rec.709, Blender's default
        ctint = tuple(c / lum for c in base) if lum > 0.0 else (1.0, 1.0, 1.0)
        color = tuple(1.0 - tint + c * tint for c in ctint)
        self._add(closure("sheen", _scale(_scale(w, color), sheen)))

    def _clearcoat(self, node, w):
        # Cycles 3.4: 0.25 x Clearcoat, IOR 1.5, alpha = Clearcoat Roughness^2, added on top of the
        # base without taking energy from it (Principled v1 is not energy conserving here either).
        coat = max(self._value(node, "Clearcoat"), 0.0)
        if coat > 0.0:
            self._add(closure("clearcoat", _scale(w, 0.25 * coat), ior=1.5,
                              roughness=_clamp01(self._value(node, "Clearcoat Roughness"))))

    def _warn_principled_extras(self, node, t):
        v = lambda name: self._value(node, name)  # noqa: E731
        ignored = [name for name in ("Subsurface", "Specular Tint", "Anisotropic") if v(name) > 0.0]
        if t > 0.0 and v("Transmission Roughness") > 0.0:
            ignored.append("Transmission Roughness")
        if node.distribution != 'GGX':
            ignored.append("Multiscatter GGX (using GGX)")
        if ignored:
            self._warn_node(node, "uses %s, not supported and ignored" % ", ".join(ignored))


def _colored(kind, w, color_in, **kwargs):
    """A closure whose colour is a textures.ColorInput: constants fold into the weight, textures
    and the object colour are per-hit inputs multiplying it."""
    weight = _scale(w, color_in.constant) if color_in.constant is not None else w
    return closure(kind, weight, **kwargs, **color_in.closure_keys())


_HANDLERS = {
    'ShaderNodeMixShader': _Translation.mix,
    'ShaderNodeAddShader': _Translation.add,
    'ShaderNodeBsdfDiffuse': _Translation.diffuse,
    'ShaderNodeBsdfGlossy': _Translation.glossy,
    'ShaderNodeBsdfGlass': _Translation.glass,
    'ShaderNodeEmission': _Translation.emission,
    'ShaderNodeBsdfPrincipled': _Translation.principled,
    'ShaderNodeBsdfTransparent': _Translation.transparent,
}


def _apply_transparency(tr):
    """Fold the Transparent BSDF weight T into the closures: the grey part g = min(T) passes by the
    cut-out (kept with probability k = 1 - g, times any Principled Alpha), so the kept hit's closures
    and emission are divided by k, and the coloured rest T - g becomes a straight-through lobe of
    weight (T - g) / k. In expectation: k (closures / k) + g = closures + g, and k (T - g) / k + g = T.
    (Light samples on an emitter are weighted by the material's alpha, so they agree with hits.)"""
    t = tuple(min(max(c, 0.0), 1.0) for c in tr.transparent)
    g = min(t)
    if max(t) <= 0.0:
        return
    keep = 1.0 - g
    if keep <= 1e-6:
        tr.closures = []
        tr.emission = BLACK
    else:
        tr.closures = [dict(c, weight=_scale(c["weight"], 1.0 / keep)) for c in tr.closures]
        tr.emission = _scale(tr.emission, 1.0 / keep)  # the engine's emitters see the cut-out too
        rest = tuple((c - g) / keep for c in t)
        if max(rest) > 0.0:
            tr.closures.append(closure("transparent", rest))
    alpha = dict(tr.alpha) if tr.alpha is not None else {"value": 1.0}
    alpha["value"] = alpha["value"] * keep
    tr.alpha = alpha


def translate(material, warn, textures=None):
    """Engine material dict for a Blender material. `warn(msg)` receives warnings; `textures`
    (a textures.TextureCache) adds images to the engine, without it texture links are ignored.
    The dict's "uv_map" names the UV map its textures read ('' the active render map, None
    when it needs no UVs)."""
    name = material.name_full
    if not material.use_nodes or material.node_tree is None:
        # What Cycles renders for a material without nodes.
        return dict({"name": name, "closures": [closure("diffuse", _rgb(material.diffuse_color))],
                     "emission": BLACK}, **material_spectral(material))

    tr = _Translation(material, warn, textures)
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
        _apply_transparency(tr)
    desc = dict({"name": name, "closures": tr.closures, "emission": tr.emission, "uv_map": tr.uv_map,
                 "volume": volume, "pass_through": pass_through}, **material_spectral(material))
    if tr.normal_map is not None:
        desc["normal_map"] = tr.normal_map
    if tr.alpha is not None:
        desc["alpha"] = tr.alpha
    if tr.emission_texture is not None:
        desc["emission_texture"] = tr.emission_texture
    return desc


class MaterialCache:
    """Adds each Blender material to the engine scene once and remembers its id."""

    def __init__(self, scene, reporter):
        self._scene = scene
        self._reporter = reporter
        self._ids = {}
        self._uv_maps = {}  # engine id -> UV map its textures read ('' = active render)
        self._textures = tex.TextureCache(scene, reporter.warning)

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
        desc = translate(material, self._reporter.warning, self._textures)
        try:
            mat_id = self._scene.add_material(desc)
            if desc.get("uv_map") is not None:
                self._uv_maps[mat_id] = desc["uv_map"]
            return mat_id
        except ValueError as exc:
            self._reporter.warning("Material '%s' was refused by the engine (%s); using a "
                                   "neutral diffuse" % (material.name, exc))
            return self._scene.add_material(default_material(desc["name"]))

    def warning(self, message):
        self._reporter.warning(message)

    def replace_all(self):
        """Viewport material edits: translate every material again and replace it in the committed
        engine scene (Scene.replace_material). False when one of them cannot be replaced in place
        (the caller then builds a new scene): a material that is gone, reads another UV map, or
        changes what the scene baked at commit (cut-out, emissive, volume)."""
        for key, mat_id in self._ids.items():
            if key is None:
                continue  # the default grey never changes
            material = bpy.data.materials.get(key)
            if material is None:
                return False
            desc = translate(material, self._reporter.warning, self._textures)
            if desc.get("uv_map") != self._uv_maps.get(mat_id):
                return False
            try:
                if not self._scene.replace_material(mat_id, desc):
                    return False
            except ValueError:
                return False
        return True

    def uv_map_for(self, mat_ids):
        """The UV map a mesh with these engine materials must export, or None if none reads UVs."""
        for mat_id in mat_ids:
            if mat_id in self._uv_maps:
                return self._uv_maps[mat_id]
        return None

    def __len__(self):
        return len(self._ids)
