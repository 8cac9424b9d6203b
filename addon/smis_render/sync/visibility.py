"""Object Properties > Visibility > Ray Visibility, as Cycles 3.4 reads it (blender/object.cpp:
the object's `visible_*` flags, and for an instance those of its instancer too)."""

# engine key -> Blender's Object property
RAY_VISIBILITY = (
    ("camera", "visible_camera"),
    ("diffuse", "visible_diffuse"),
    ("glossy", "visible_glossy"),
    ("transmission", "visible_transmission"),
    ("volume_scatter", "visible_volume_scatter"),
    ("shadow", "visible_shadow"),
)


def ray_visibility(obj, instancer=None):
    """The engine's visibility dict of `obj` (instanced by `instancer`, or None), or None when every
    ray sees it (the engine's default, so scenes without hidden objects pass nothing)."""
    owners = [o for o in (obj, instancer) if o is not None]
    flags = {key: all(bool(getattr(o, prop, True)) for o in owners) for key, prop in RAY_VISIBILITY}
    return None if all(flags.values()) else flags


def instance_ray_visibility(inst):
    """ray_visibility of a depsgraph object instance."""
    instancer = inst.parent if inst.is_instance and inst.parent is not None else None
    return ray_visibility(inst.object, instancer)
