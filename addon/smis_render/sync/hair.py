"""Hair -> engine curves (Scene.add_curves), read as Cycles 3.4 reads it (intern/cycles/blender/curves.cpp).

* Particle-system hair (Particle Settings of type Hair, rendered as Path) of an evaluated object:
  every strand the render depsgraph evaluates (parents, or the children when there are any) through
  `ParticleSystem.co_hair` at 2^render_step + 1 steps (world space), steps of zero length dropped as
  Cycles drops them. Radius along the strand from the Hair Shape panel: Cycles' root and tip radius
  (Diameter Root / Tip x Radius Scale x 0.5) blended by Strand Shape over the strand's length, 0 at
  the last point with Close Tip. Material: the settings' material slot.
* Curves objects (3.4's hair curves): `position`, the `radius` attribute (Cycles' 0.005 without one)
  and the curve offsets, all through foreach_get; the first material slot.
* Hair Info's Random (and the Principled Hair BSDF's default Random): Cycles hashes each strand's
  index in its object's hair, counted over the object's particle systems in modifier order
  (instances.py passes add_curves the running count), so the strands vary as in Cycles.

* Curve Shape: "3D Curves" as round Catmull-Rom curves, "Rounded Ribbons" as flat ones facing the
  ray with Cycles' faked round normal (Scene.set_curve_ribbons, its Subdivisions).
* Strand UVs (when the material reads UVs or attributes): Cycles gives every strand the emitter's
  UV maps at its root, constant along the strand (ATTR_ELEMENT_CURVE): particle hair through
  `ParticleSystem.uv_on_emitter` (the parent particle for parents, the first one for children, as
  Cycles passes them), the render-active map as the default UV and every map by name; a Curves
  object's first float2 attribute on the curve domain (3.4: `surface_uv_coordinate`) as the default
  UV and its curve-domain float2 attributes by name. Particle hair also carries the emitter's byte
  colour layers at the roots by name (mcol_on_emitter, sRGB to linear as Cycles).

`co_hair` is one Python call per point (no bulk accessor exists for evaluated children in 3.4):
about 14 us each, 0.38 s for 3,000 strands of 9 points (measured on this machine).
"""

import numpy as np

# Cycles' radius of hair curves without a radius attribute.
CURVES_DEFAULT_RADIUS = 0.005


def _strand_radius(times, shape, root, tip):
    """Cycles' shaperadius: root at time 0, tip at time 1, Strand Shape bending the blend."""
    radius = 1.0 - times
    if shape < 0.0:
        radius = radius ** (1.0 + shape)
    elif shape > 0.0:
        radius = radius ** (1.0 / (1.0 - shape))
    return radius * (root - tip) + tip


def ribbon_subdivisions(scene):
    """Cycles' Curve Shape (Render Properties > Curves): the Subdivisions of "Rounded Ribbons"
    (RIBBONS), or None for "3D Curves" (THICK, the default)."""
    curves = getattr(scene, "cycles_curves", None)
    if curves is None or curves.shape != 'RIBBONS':
        return None
    return max(int(curves.subdivisions), 0)


def particle_hair_systems(obj):
    """The particle systems of an evaluated object that Cycles renders as hair curves, in its order
    (the modifiers', which numbers the strands for Hair Info's Random)."""
    return [m.particle_system for m in obj.modifiers
            if m.type == 'PARTICLE_SYSTEM' and m.show_render and m.particle_system.settings.type == 'HAIR'
            and m.particle_system.settings.render_type == 'PATH']


def particle_strands(obj, psys):
    """(points (N, 4) float32 in object space: x, y, z, radius; offsets (curves + 1,) int32)."""
    st = psys.settings
    steps = (1 << st.render_step) + 1
    if st.kink == 'SPIRAL':
        steps += st.kink_extra_steps
    parents, children = len(psys.particles), len(psys.child_particles)
    first = parents if st.child_type != 'NONE' and children else 0
    count = parents + children - first
    world = np.empty((count * steps, 3), dtype=np.float32)
    co_hair = psys.co_hair
    k = 0
    for pa in range(first, parents + children):
        for step in range(steps):
            world[k] = co_hair(obj, particle_no=pa, step=step)
            k += 1
    inv = np.array(obj.matrix_world.inverted_safe(), dtype=np.float64)
    local = (world.astype(np.float64) @ inv[:3, :3].T + inv[:3, 3]).reshape(count, steps, 3)
    # Steps of zero length are dropped (Cycles), the rest measured along the strand.
    seg = np.linalg.norm(np.diff(local, axis=1), axis=2)
    keep = np.concatenate([np.ones((count, 1), dtype=bool), seg > 0.0], axis=1)
    lengths = np.concatenate([np.zeros((count, 1)), np.cumsum(np.where(seg > 0.0, seg, 0.0), axis=1)], axis=1)
    total = lengths[:, -1:]
    times = np.divide(lengths, total, out=np.zeros_like(lengths), where=total > 0.0)
    half = st.radius_scale * 0.5
    radius = _strand_radius(times, st.shape, half * st.root_radius, half * st.tip_radius)
    if st.use_close_tip:
        last = np.cumsum(keep, axis=1) == keep.sum(axis=1, keepdims=True)
        radius = np.where(last & keep, 0.0, radius)
    points = np.concatenate([local, radius[..., None]], axis=2)[keep].astype(np.float32)
    offsets = np.concatenate([[0], np.cumsum(keep.sum(axis=1))]).astype(np.int32)
    return points, offsets


def particle_material(obj, psys):
    """The material of a hair particle system: its settings' slot (1-based), clamped as Cycles does."""
    slots = obj.material_slots
    if not len(slots):
        return None
    return slots[min(max(psys.settings.material - 1, 0), len(slots) - 1)].material


def curves_strands(curves):
    """(points, offsets) of a Curves datablock (object space)."""
    n = len(curves.points)
    pos = np.empty(n * 3, dtype=np.float32)
    curves.points.foreach_get("position", pos)
    radius = np.full(n, CURVES_DEFAULT_RADIUS, dtype=np.float32)
    if "radius" in curves.attributes:
        curves.attributes["radius"].data.foreach_get("value", radius)
    offsets = np.empty(len(curves.curves) + 1, dtype=np.int32)
    curves.curve_offset_data.foreach_get("value", offsets)
    points = np.concatenate([pos.reshape(n, 3), radius[:, None]], axis=1)
    return np.ascontiguousarray(points, dtype=np.float32), offsets


def curves_material(obj):
    slots = obj.material_slots
    return slots[0].material if len(slots) else None


def _particle_modifier(obj, psys):
    return next(m for m in obj.modifiers if m.type == 'PARTICLE_SYSTEM' and m.particle_system == psys)


def _strand_roots(psys):
    """[(particle_no, particle)] per strand in particle_strands' order (the children when there are
    any, else the parents): what uv_on_emitter / mcol_on_emitter take for the strand's root. Cycles'
    particle iterator stays on the first particle for children."""
    parents, children = len(psys.particles), len(psys.child_particles)
    first = parents if psys.settings.child_type != 'NONE' and children else 0
    return [(pa, psys.particles[pa if pa < parents else 0]) for pa in range(first, parents + children)]


def particle_uvs(obj, psys, uv_map):
    """(uvs (strands, 2) float32 of the map `uv_map` ('' = the render-active one), {name: (strands, 2)}
    of every map) at the strands' roots on the emitter, in particle_strands' order; (None, {}) when
    the emitter has no UV map. One uv_on_emitter call per strand and map."""
    layers = list(getattr(obj.data, "uv_layers", ()))
    if not layers:
        return None, {}
    roots = _strand_roots(psys)
    mod = _particle_modifier(obj, psys)
    per_map = {}
    for uv_no, layer in enumerate(layers):
        uv = np.empty((len(roots), 2), dtype=np.float32)
        for k, (pa, particle) in enumerate(roots):
            uv[k] = psys.uv_on_emitter(mod, particle=particle, particle_no=pa, uv_no=uv_no)
        per_map[layer.name] = uv
    default = per_map.get(uv_map) if uv_map else None
    if default is None:
        active = next((l for l in layers if l.active_render), layers[0])
        default = per_map[active.name]
    per_map.update(_particle_colors(obj, psys, mod, roots))
    return default, per_map


def _srgb_to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def _particle_colors(obj, psys, mod, roots):
    """{name: (strands, 4)}: the emitter's byte colour layers (mesh.vertex_colors) at each strand's
    root (`roots`: _strand_roots), by name, as Cycles' ObtainCacheParticleVcol reads them
    (mcol_on_emitter, sRGB bytes) and stores them (color_srgb_to_linear, alpha 1)."""
    out = {}
    for vcol_no, layer in enumerate(getattr(obj.data, "vertex_colors", ())):
        col = np.ones((len(roots), 4), dtype=np.float32)
        for k, (pa, particle) in enumerate(roots):
            col[k, :3] = psys.mcol_on_emitter(mod, particle=particle, particle_no=pa, vcol_no=vcol_no)
        col[:, :3] = _srgb_to_linear(col[:, :3])
        out[layer.name] = col
    return out


def curves_uvs(curves):
    """(uvs (curves, 2) or None, {name: (curves, 2)}): a Curves datablock's float2 attributes on the
    curve domain, the first of them its default UV (Cycles 3.4's export_hair_curves)."""
    per_map = {}
    n = len(curves.curves)
    for attr in curves.attributes:
        if attr.data_type == 'FLOAT2' and attr.domain == 'CURVE' and len(attr.data) == n:
            uv = np.empty(n * 2, dtype=np.float32)
            attr.data.foreach_get("vector", uv)
            per_map[attr.name] = uv.reshape(n, 2)
    default = next(iter(per_map.values()), None)
    return default, per_map
