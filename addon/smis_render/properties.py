"""Render settings stored on the scene as `scene.smis`."""

import math

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
    # Cycles' Light Paths > Max Bounces per type, Clamping and Caustics (light_path_settings). Unlike
    # Cycles' defaults (diffuse and glossy 4, indirect clamp 10, Filter Glossy 1), ours leave the image
    # unbiased: only Max Bounces limits paths, nothing is clamped or blurred, caustics are on.
    diffuse_bounces: IntProperty(
        name="Diffuse",
        description="Maximum number of diffuse reflection bounces, as Cycles' (bounded by Max Bounces); "
                    "a lower limit darkens indirect diffuse light",
        default=1024, min=0, soft_max=64,
    )
    glossy_bounces: IntProperty(
        name="Glossy",
        description="Maximum number of glossy reflection bounces, as Cycles' (bounded by Max Bounces)",
        default=1024, min=0, soft_max=64,
    )
    transmission_bounces: IntProperty(
        name="Transmission",
        description="Maximum number of transmission bounces, as Cycles' (bounded by Max Bounces)",
        default=1024, min=0, soft_max=64,
    )
    transparent_bounces: IntProperty(
        name="Transparent",
        description="Maximum number of passes through coloured transparency (Transparent BSDF) as Cycles'; "
                    "grey alpha cut-outs are decided in the ray query and count none",
        default=1024, min=0, soft_max=64,
    )
    clamp_direct: FloatProperty(
        name="Direct Light",
        description="Cycles' Clamp Direct: the largest value (sum of RGB) a sample's direct light may add, "
                    "0 = off. Clamping removes fireflies but biases (darkens) the image",
        default=0.0, min=0.0, soft_max=100.0,
    )
    clamp_indirect: FloatProperty(
        name="Indirect Light",
        description="Cycles' Clamp Indirect: the largest value (sum of RGB) a sample's indirect light may "
                    "add, 0 = off. Clamping removes fireflies but biases (darkens) the image",
        default=0.0, min=0.0, soft_max=100.0,
    )
    caustics_reflective: BoolProperty(
        name="Reflective Caustics",
        description="Cycles' Reflective Caustics: off, surfaces reached by diffuse bounces leave out their "
                    "glossy reflection; less noise, but the image is biased (darker)",
        default=True,
    )
    caustics_refractive: BoolProperty(
        name="Refractive Caustics",
        description="Cycles' Refractive Caustics: off, surfaces reached by diffuse bounces leave out their "
                    "refraction; less noise, but the image is biased (darker)",
        default=True,
    )
    filter_glossy: FloatProperty(
        name="Filter Glossy",
        description="Cycles' Filter Glossy: after diffuse or rough bounces, glossy surfaces are rendered "
                    "rougher (by the path's smallest sampling density), 0 = off. Less noise from caustics, "
                    "but the image is biased",
        default=0.0, min=0.0, soft_max=10.0,
    )
    viewport_samples: IntProperty(
        name="Viewport Samples",
        description="Samples per pixel of the interactive viewport (Rendered shading); it refines "
                    "progressively up to this and restarts after every edit",
        default=32, min=1, soft_max=1024,
    )
    viewport_resolution_divider: IntProperty(
        name="Viewport Pixel Size",
        description="Render the viewport at 1/N of its resolution and scale it up: N^2 times "
                    "fewer paths per refinement",
        default=2, min=1, max=8,
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
    sampling_pattern: EnumProperty(
        name="Pattern",
        description="Random numbers of the pixel samples",
        items=[
            ('STRATIFIED', "Stratified",
             "Owen-scrambled Sobol points for the pixel position, the lens and the first bounce's light "
             "and BSDF samples, so a pixel's samples spread evenly; independent random numbers after. "
             "Unbiased, less noise at the same samples, negligible cost"),
            ('RANDOM', "Random", "Independent random numbers for every decision (for comparisons)"),
        ],
        default='STRATIFIED',
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
            ('PSF_SMIS', "Path-Space Filtering (SMIS)",
             "Reuses the indirect light of nearby paths, weighted by stochastic MIS (West et al. 2020, "
             "eq. 17). Biased (no visibility in the weights, reused scattering), much less noise"),
            ('PSF_KELLER', "Path-Space Filtering (Keller)",
             "Keller et al. 2014: reuses nearby paths accepted by surface similarity. Biased"),
            ('PSF_SMIS_UNBIASED', "Path-Space Filtering (SMIS, unbiased)",
             "Eq. 17 with exact visibility and scattering for every connection and density: "
             "unbiased but costly (one shadow ray per technique pair)"),
            ('PSF_PATH', "Path-Space Filtering: no reuse",
             "The path tracer on the paths of the two-stage filtering pipeline (baseline)"),
        ],
        default='PATH',
    )
    psf_radius_px: FloatProperty(
        name="Filter Radius",
        description="Radius in screen pixels, projected to world space at each path's first "
                    "non-specular vertex, within which paths share their indirect light. Larger "
                    "reuses more (less noise, more blur); cost grows with the neighbours gathered",
        default=6.0, min=0.1, soft_max=32.0, subtype='PIXEL',
    )
    psf_radius_alpha: FloatProperty(
        name="Radius Shrink",
        description="Progressive shrink of the radius, r_i = r_0 (i+1)^((alpha-1)/2) as in "
                    "progressive photon mapping: 1 keeps it fixed, smaller shrinks faster",
        default=2.0 / 3.0, min=0.05, max=1.0,
    )
    psf_max_neighbors: IntProperty(
        name="Max Neighbours",
        description="Most paths combined per pixel (a random subset beyond this). The SMIS weights "
                    "cost the square of this per set of gathered paths (see Shared Sets)",
        default=24, min=1, soft_max=128,
    )
    psf_light_samples: IntProperty(
        name="Light Samples",
        description="Light samples per iteration at each path's first non-specular vertex, whose "
                    "direct light stays per pixel while the indirect light is shared (multi-sample "
                    "MIS with the BSDF sample). More cost a shadow ray each",
        default=4, min=1, soft_max=16,
    )
    psf_extra_paths: IntProperty(
        name="Extra Paths",
        description="Most extra paths per iteration from a pixel's first non-specular vertex where "
                    "the filter cannot share its path (sharp lobes, thin or curved glossy objects): "
                    "in proportion to the weight its own path keeps in its estimate. 0 = off",
        default=4, min=0, max=255, soft_max=16,
    )
    psf_block_size: IntProperty(
        name="Shared Sets",
        description="Side of the pixel blocks (1, 2 or 4) whose pixels share one set of gathered "
                    "paths, when their first vertices are close: the SMIS denominators are computed "
                    "once per block rather than once per pixel. 1 = every pixel gathers on its own",
        default=2, min=1, max=4,
    )
    psf_keller_normal_cos: FloatProperty(
        name="Keller Normal Cosine",
        description="Keller et al. weighting: accept a neighbour only if the cosine between the "
                    "shading normals is at least this",
        default=0.9, min=-1.0, max=1.0,
    )
    psf_keller_plane: FloatProperty(
        name="Keller Plane Distance",
        description="Keller et al. weighting: accept a neighbour only if its distance to the "
                    "query's tangent plane is at most this fraction of the radius",
        default=0.1, min=0.0, soft_max=1.0,
    )

    spectral: EnumProperty(
        name="Spectral",
        description="Spectral rendering and its wavelength sampling (West et al. 2020, §5)",
        items=[
            ('AUTO', "Auto", "RGB when nothing in the scene has a spectrum (light or emission "
                             "spectra, measured metals, dispersion) or with photon planes, "
                             "otherwise SMIS"),
            ('RGB', "RGB", "No spectral sampling: fastest, ignores spectra"),
            ('UNIFORM', "Uniform", "One wavelength per path, uniformly sampled"),
            ('SPECTRAL_IS', "Spectral IS", "One wavelength per path, importance sampled from the "
                                           "observer response times the lights' spectra"),
            ('HERO', "Hero Wavelength", "Wilkie et al. 2014: one importance-sampled hero, the "
                                        "others equally spaced, balance heuristic (eq. 19)"),
            ('SMIS', "SMIS", "Every wavelength importance sampled (stratified), balance heuristic "
                             "(eq. 21)"),
            ('SMIS_INDEPENDENT', "SMIS (independent)", "SMIS with independent wavelengths"),
            ('BRUTE_FORCE', "Brute Force (512)", "512 wavelengths per path: reference only"),
        ],
        default='AUTO',
    )
    wavelengths: IntProperty(
        name="Wavelengths",
        description="Wavelengths evaluated per path by Hero and SMIS",
        default=4, min=1, max=64,
    )
    volume_estimator: EnumProperty(
        name="Volume Estimator",
        description="How single scattering in participating media is estimated (volume bounces "
                    "= 0). The photon-plane estimators (West et al. 2020, Sec. 6) handle the "
                    "camera rays' scattering of light from rectangular area lights in homogeneous "
                    "media; everything else comes from the path tracer",
        items=[
            ('PATH', "Path Tracing",
             "Distance sampling and next event estimation on every ray (the reference)"),
            ('PLANES_UNWEIGHTED', "Photon Planes",
             "Each plane from one orientation (eq. 22): has the 1/|cos| singularity where camera "
             "rays run parallel to a plane"),
            ('PLANES_CMIS', "Photon Planes, CMIS (Deng et al.)",
             "Deng et al. 2019's closed-form weighting over all plane orientations (eq. 26)"),
            ('PLANES_SMIS_COS', "Photon Planes, SMIS (cosine)",
             "Stochastic MIS over n stratified orientations with cosine-only densities"),
            ('PLANES_SMIS_EXACT', "Photon Planes, SMIS (exact)",
             "Stochastic MIS over n stratified orientations with the exact densities, including "
             "the plane width (eq. 25, 27): down-weights thin bright planes"),
        ],
        default='PATH',
    )
    photon_planes: IntProperty(
        name="Photon Planes",
        description="Photon planes traced per iteration (one iteration per camera sample); a fresh "
                    "set each iteration, the iterations are averaged",
        default=40960, min=1, soft_max=1000000,
    )
    smis_planes: IntProperty(
        name="SMIS Orientations",
        description="n, the number of stratified plane orientations per SMIS realisation (eq. 27); "
                    "with 2 the partner plane is perpendicular and only weighted",
        default=2, min=1, max=64,
    )
    plane_shadow_rays: IntProperty(
        name="Shadow Rays per Camera Ray",
        description="About this many of a camera ray's plane crossings trace their shadow ray, chosen "
                    "by their unshadowed contribution and reweighted (Russian roulette: unbiased); "
                    "0 traces one for every crossing",
        default=0, min=0, soft_max=1024,
    )
    plane_surface_samples: IntProperty(
        name="Surface Samples per Plane Set",
        description="Path-tracer samples per pixel that one plane set serves (surfaces, other lights, "
                    "secondary rays), so surfaces converge at the path tracer's pace; 0 chooses it from "
                    "the plane set's gathering cost",
        default=0, min=0, soft_max=64,
    )
    # Many-light direct illumination (integrator PATH), at the camera path's first non-specular vertex.
    direct_light: EnumProperty(
        name="Direct Light",
        description="How the path tracer samples the direct light at the first non-specular surface "
                    "seen from the camera (deeper bounces always use next event estimation)",
        items=[
            ('NEE', "Next Event Estimation",
             "One light chosen by power, one point on it, MIS with BSDF sampling"),
            ('RIS', "Resampled (RIS)",
             "Resampled importance sampling: M light candidates, one chosen by its unshadowed "
             "contribution, one shadow ray. Unbiased"),
            ('RESTIR', "ReSTIR",
             "RIS, then reuse of reservoirs from neighbouring pixels and from the previous sample of "
             "the same pixel (Bitterli et al. 2020). Each sample is a whole-image pass"),
        ],
        default='NEE',
    )
    ris_candidates: IntProperty(
        name="Candidates",
        description="Light candidates per pixel and sample (M) for RIS and ReSTIR. More candidates "
                    "follow the unshadowed contribution more closely, at the cost of one light "
                    "sample and BSDF evaluation each (no shadow ray)",
        default=16, min=1, soft_max=256,
    )
    restir_neighbors: IntProperty(
        name="Neighbours",
        description="Pixels whose reservoirs are reused per pixel (k). The MIS weights cost k "
                    "pdf evaluations with Seed MIS and k squared with Talbot MIS",
        default=5, min=0, soft_max=32,
    )
    restir_radius_px: FloatProperty(
        name="Neighbour Radius",
        description="Neighbours are drawn uniformly from a disk of this radius around the pixel, "
                    "among pixels whose surface is similar (normals, distance). Close neighbours share "
                    "the visibility, so a few pixels work best (measured at 128 px: 3 beat 5); Bitterli "
                    "et al. use 30 at 1920x1080",
        default=3.0, min=1.0, soft_max=100.0, subtype='PIXEL',
    )
    restir_history_cap: IntProperty(
        name="History Cap",
        description="The previous sample's reservoir of the same pixel counts as at most this many "
                    "times M candidates (the offline analogue of temporal reuse); 0 disables that reuse "
                    "and makes every sample independent. The samples are averaged and a history "
                    "correlates them: on the many-light scene it did not lower the error per sample "
                    "and cost time, so it is off by default",
        default=0, min=0, soft_max=100,
    )
    restir_mis: EnumProperty(
        name="Reuse MIS",
        description="How reservoirs from different pixels are weighted against each other",
        items=[
            ('SEED', "Seed MIS",
             "One MIS weight for the selected sample: k pdf evaluations (ReSTIR supplement, Alg. 1)"),
            ('TALBOT', "Talbot MIS",
             "An MIS weight for every reused sample: k squared pdf evaluations (Alg. 2)"),
            ('NONE', "None (1/M, biased)",
             "Plain normalisation by the candidate count: cheapest, biased (darker) where neighbours "
             "cannot produce the sample, e.g. near shadows"),
        ],
        default='SEED',
    )
    restir_unbiased: BoolProperty(
        name="Unbiased",
        description="Trace the visibility of the selected sample from each neighbour for the MIS "
                    "weights, so neighbours that cannot see it get zero weight. Off skips those "
                    "shadow rays: faster, but biased (darker) near shadows. Only matters with "
                    "Visibility Reuse",
        default=True,
    )
    restir_visibility_reuse: BoolProperty(
        name="Visibility Reuse",
        description="Drop each pixel's initial sample when it is occluded (one shadow ray) before "
                    "reuse, so neighbours share only visible samples. Off keeps occluded samples: "
                    "then the MIS weights need no visibility and stay unbiased",
        default=True,
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


def film_exposure(scene):
    """The scene's Film > Exposure, a linear factor on the image's light (Cycles' `film_exposure`:
    it scales the Combined colour, not alpha nor data passes such as Depth, Normal or Albedo).

    It is a Cycles setting (Cycles' Film panel), but the scene carries it: a scene set up for Cycles
    with Exposure 10 must come out 10 times as bright from SMIS too. Without the Cycles add-on its
    value is still stored in the scene's "cycles" ID properties (absent there means the default 1)."""
    cycles = getattr(scene, "cycles", None)
    if cycles is not None and hasattr(cycles, "film_exposure"):
        value = cycles.film_exposure
    else:
        stored = scene.get("cycles")
        value = stored.get("film_exposure", 1.0) if hasattr(stored, "get") else 1.0
    try:
        value = float(value)
    except (TypeError, ValueError):
        return 1.0
    return value if math.isfinite(value) and value >= 0.0 else 1.0


def _cycles_scene_setting(scene, name, default):
    """A setting of Cycles' own panels that the scene carries (without the Cycles add-on: in the
    scene's "cycles" ID properties, absent meaning Cycles' default)."""
    cycles = getattr(scene, "cycles", None)
    if cycles is not None and hasattr(cycles, name):
        return getattr(cycles, name)
    stored = scene.get("cycles")
    return stored.get(name, default) if hasattr(stored, "get") else default


# Light Paths settings: ours (scene.smis) -> Cycles' name in scene.cycles.
LIGHT_PATH_SETTINGS = (
    ("diffuse_bounces", "diffuse_bounces"),
    ("glossy_bounces", "glossy_bounces"),
    ("transmission_bounces", "transmission_bounces"),
    ("transparent_bounces", "transparent_max_bounces"),
    ("clamp_direct", "sample_clamp_direct"),
    ("clamp_indirect", "sample_clamp_indirect"),
    ("caustics_reflective", "caustics_reflective"),
    ("caustics_refractive", "caustics_refractive"),
    ("filter_glossy", "blur_glossy"),
)


def light_path_source(scene, ours, cycles_name):
    """Where a Light Paths setting comes from: (owner, property name). Ours once set; else the
    scene's Cycles setting when the scene sets it (a scene made for Cycles renders with its limits,
    clamps and caustics); else ours, whose defaults leave the image unbiased."""
    settings = scene.smis
    if settings.is_property_set(ours):
        return settings, ours
    cycles = getattr(scene, "cycles", None)
    if cycles is not None and hasattr(cycles, cycles_name):
        if cycles.is_property_set(cycles_name):
            return cycles, cycles_name
    else:  # without the Cycles add-on its settings are the scene's "cycles" ID properties
        stored = scene.get("cycles")
        if hasattr(stored, "get") and stored.get(cycles_name) is not None:
            return stored, cycles_name
    return settings, ours


def light_path_settings(scene):
    """The engine's per-type bounce limits, clamps and caustics toggles for the scene."""
    out = {}
    for ours, cycles_name in LIGHT_PATH_SETTINGS:
        owner, name = light_path_source(scene, ours, cycles_name)
        value = getattr(owner, name) if isinstance(owner, bpy.types.bpy_struct) else owner[name]
        out[ours] = type(getattr(scene.smis, ours))(value)
    return out


def film_transparent_glass(scene):
    """Cycles' Film > Transparent Glass as the engine takes it: the roughness threshold under which
    glass lets the World through as alpha, or -1 when off (it needs Film > Transparent)."""
    if not scene.render.film_transparent or not _cycles_scene_setting(scene, "film_transparent_glass", False):
        return -1.0
    try:
        value = float(_cycles_scene_setting(scene, "film_transparent_roughness", 0.1))
    except (TypeError, ValueError):
        return -1.0
    return value if math.isfinite(value) and value >= 0.0 else -1.0


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
        **light_path_settings(scene),
        # Blender's Film > Transparent (a scene.render setting: Cycles' own Film panel shows it)
        "film_transparent": bool(scene.render.film_transparent),
        "film_transparent_glass": film_transparent_glass(scene),
        "seed": seed,
        "stratified": s.sampling_pattern == 'STRATIFIED',
        "mis_heuristic": s.mis_heuristic,
        "time_limit": float(s.time_limit),
        "threads": threads,
        "integrator": s.integrator,
        "filter": s.filter_type,
        "psf_radius_px": float(s.psf_radius_px),
        "psf_radius_alpha": float(s.psf_radius_alpha),
        "psf_max_neighbors": s.psf_max_neighbors,
        "psf_light_samples": s.psf_light_samples,
        "psf_extra_paths": s.psf_extra_paths,
        "psf_block_size": s.psf_block_size,
        "psf_keller_normal_cos": float(s.psf_keller_normal_cos),
        "psf_keller_plane": float(s.psf_keller_plane),
        "filter_width": float(s.filter_width),
        "spectral": s.spectral,
        "wavelengths": s.wavelengths,
        "volume_estimator": s.volume_estimator,
        "photon_planes": s.photon_planes,
        "smis_planes": s.smis_planes,
        "plane_shadow_rays": s.plane_shadow_rays,
        "plane_surface_samples": s.plane_surface_samples,
        "direct_light": s.direct_light,
        "ris_candidates": s.ris_candidates,
        "restir_neighbors": s.restir_neighbors,
        "restir_radius_px": float(s.restir_radius_px),
        "restir_history_cap": s.restir_history_cap,
        "restir_mis": s.restir_mis,
        "restir_unbiased": bool(s.restir_unbiased),
        "restir_visibility_reuse": bool(s.restir_visibility_reuse),
    }


def register():
    bpy.utils.register_class(SMISRenderSettings)
    bpy.types.Scene.smis = PointerProperty(type=SMISRenderSettings, name="SMIS Render Settings")


def unregister():
    del bpy.types.Scene.smis
    bpy.utils.unregister_class(SMISRenderSettings)
