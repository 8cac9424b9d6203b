"""Render settings stored on the scene as `scene.smis`."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty


class SMISRenderSettings(bpy.types.PropertyGroup):
    samples: IntProperty(
        name="Samples",
        description="Number of samples (paths) per pixel",
        default=64, min=1, soft_max=4096,
    )
    max_bounces: IntProperty(
        name="Max Bounces",
        description="Maximum number of bounces of a path, as Cycles' Max Bounces: "
                    "0 renders direct lighting only",
        default=8, min=0, soft_max=64,
    )
    seed: IntProperty(
        name="Seed",
        description="Seed of the random numbers; different seeds give different noise patterns",
        default=0, min=0,
    )
    use_animated_seed: BoolProperty(
        name="Animated Seed",
        description="Add the frame number to the seed, so that the noise pattern changes "
                    "every frame",
        default=False,
    )
    mis_heuristic: EnumProperty(
        name="MIS Heuristic",
        description="How multiple importance sampling weights the sampling techniques",
        items=[
            ('BALANCE', "Balance", "Balance heuristic: weights proportional to the pdfs"),
            ('POWER', "Power", "Power heuristic (exponent 2): favours the locally best technique"),
        ],
        default='POWER',
    )
    time_limit: FloatProperty(
        name="Time Limit",
        description="Stop rendering after this many seconds, even if not all samples are done "
                    "(0 means no limit)",
        default=0.0, min=0.0, subtype='TIME_ABSOLUTE', unit='TIME_ABSOLUTE',
    )
    threads: IntProperty(
        name="Threads",
        description="Number of render threads; 0 uses all cores, or Blender's fixed thread "
                    "count when Threads Mode is Fixed (-t N on the command line)",
        default=0, min=0, soft_max=256,
    )
    # An enum, not a bool: more integrators will be added to the engine's registry.
    integrator: EnumProperty(
        name="Integrator",
        description="Light transport algorithm",
        items=[
            ('PATH', "Path Tracing",
             "Unidirectional path tracing with next event estimation and MIS"),
        ],
        default='PATH',
    )

    filter_type: EnumProperty(
        name="Pixel Filter",
        description="Pixel reconstruction filter, importance-sampled as in Cycles (no extra cost)",
        items=[
            ('BLACKMAN_HARRIS', "Blackman-Harris", "Cycles' default: sharp, little ringing"),
            ('GAUSSIAN', "Gaussian", "Softer"),
            ('BOX', "Box", "Each sample stays inside its pixel"),
        ],
        default='BLACKMAN_HARRIS',
    )
    filter_width: FloatProperty(
        name="Filter Width",
        description="Pixel filter width in pixels (Cycles' default is 1.5)",
        default=1.5, min=0.01, soft_max=10.0, subtype='PIXEL',
    )


def session_settings(scene):
    """The settings dict for `_smis.RenderSession`, resolved for the scene's current frame."""
    s = scene.smis
    seed = s.seed + (scene.frame_current if s.use_animated_seed else 0)
    seed %= 2 ** 31  # negative frames must still give a valid, distinct engine seed
    threads = s.threads
    if threads == 0 and scene.render.threads_mode == 'FIXED':
        threads = scene.render.threads
    return {
        "samples": s.samples,
        "max_bounces": s.max_bounces,
        "seed": seed,
        "mis_heuristic": s.mis_heuristic,
        "time_limit": float(s.time_limit),
        "threads": threads,
        "integrator": s.integrator,
        "filter": s.filter_type,
        "filter_width": float(s.filter_width),
    }


def register():
    bpy.utils.register_class(SMISRenderSettings)
    bpy.types.Scene.smis = PointerProperty(type=SMISRenderSettings, name="SMIS Render Settings")


def unregister():
    del bpy.types.Scene.smis
    bpy.utils.unregister_class(SMISRenderSettings)
