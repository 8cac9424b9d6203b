"""Cycles as an unbiased reference (BLENDER_NOTES: its 3.4 defaults cap bounces per type, blur
glossy, clamp, skip dim lights, denoise and sample adaptively). Shared by the scene builder, the
reference renderer and the benchmarks, so every Cycles image in the project uses the same settings."""


def make_cycles_unbiased(scene, max_bounces=None):
    c = scene.cycles
    c.device = 'CPU'
    c.use_denoising = False
    c.use_preview_denoising = False
    c.use_adaptive_sampling = False
    n = c.max_bounces if max_bounces is None else max_bounces
    c.max_bounces = n
    c.diffuse_bounces = n
    c.glossy_bounces = n
    c.transmission_bounces = n
    # Scenes for single scattering (photon planes) store smis_volume_bounces = 0: Cycles' volume
    # bounces 0 is our single-scattering reference.
    c.volume_bounces = scene.get("smis_volume_bounces", n)
    c.transparent_max_bounces = n
    c.blur_glossy = 0.0
    c.light_sampling_threshold = 0.0
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    # Our tests compare with a 1 px box filter (the engine supports Cycles' Blackman-Harris too).
    c.pixel_filter_type = 'BOX'
    c.filter_width = 1.0
    scene.render.filter_size = 1.0  # the same property seen from the render settings
