"""The render settings, one table: every setting's name, type, default, limits, enum items, the
Blender property and where the UI shows it, and the engine's C++ field with the reason for its
default.

Everything else is generated from this table:
* `engine/render/tools/gen_settings.py` writes the C++ `RenderSettings` struct, the settings enums
  and the parser of the settings dict (`render_settings.h`, at build time);
* `properties.py` builds `scene.smis`'s Blender properties from it;
* `ui.py` draws the render panels from it;
* `properties.session_settings` builds the engine's settings dict from it.

Adding a setting is one `Setting(...)` line here (plus the code that uses it). The engine rejects a
key it does not know, so a misspelt key is an error, never a silent default.

Pure data: importable without Blender (the generator runs under the system Python at build time).
"""

from collections import namedtuple

EnumItem = namedtuple("EnumItem", "id cpp name description")


class Enum:
    """An enum setting's values: Blender's item ids (the settings dict's strings) and the C++
    enumerators of `cpp_type`. `defined_in`: a header that already defines the C++ enum (the
    generator then only maps the names)."""

    def __init__(self, cpp_type, items, defined_in=None):
        self.cpp_type = cpp_type
        self.items = [EnumItem(*item) for item in items]
        self.defined_in = defined_in

    def ids(self):
        return [item.id for item in self.items]


class Setting:
    """One render setting.

    key        the engine's settings-dict key and, unless `prop` says otherwise, the Blender property
    kind       'int', 'uint', 'float', 'double', 'bool' or an `Enum`
    default    the default, in Blender's terms (an enum's item id)
    name, description: the Blender property's label and tooltip
    why        the C++ field's comment: why the default is what it is (optional)
    field      the C++ field (default: key)
    prop       the Blender property's name; None: engine only (the add-on derives it, see `session`)
    engine     False: a Blender property the engine never sees (viewport, animated seed, ...)
    min/max    hard limits, checked by the engine's parser and enforced by Blender
    soft_min/soft_max, subtype, unit: Blender's slider range and display
    panel      the render panel that shows it (ui.py); None: not shown there
    show       settings -> bool: shown only when true; active: settings -> bool: greyed out when false
    beside     draw it in the row of this other setting, as an icon toggle (Cycles' animated seed)
    cycles     the Cycles setting (scene.cycles) a scene made for Cycles gives it (Light Paths)
    session    (scene, settings) -> value: how the add-on derives the engine's value when it is not
               simply the property's (seed with the frame, threads from Blender's thread mode)
    """

    def __init__(self, key, kind, default, name="", description="", why="", field=None, prop="", engine=True,
                 min=None, max=None, soft_min=None, soft_max=None, subtype=None, unit=None, panel=None,
                 show=None, active=None, beside=None, cycles=None, session=None):
        self.key = key
        self.kind = kind
        self.default = default
        self.name = name
        self.description = description
        self.why = why
        self.field = field or key
        self.prop = key if prop == "" else prop
        self.engine = engine
        self.min, self.max, self.soft_min, self.soft_max = min, max, soft_min, soft_max
        self.subtype, self.unit = subtype, unit
        self.panel, self.show, self.active, self.beside = panel, show, active, beside
        self.cycles = cycles
        self.session = session

    @property
    def is_enum(self):
        return isinstance(self.kind, Enum)


MIS_HEURISTIC = Enum("MisHeuristic", [
    ("BALANCE", "Balance", "Balance", "Balance heuristic: weights proportional to the pdfs"),
    ("POWER", "Power", "Power", "Power heuristic (exponent 2): favours the locally best technique"),
], defined_in="core/sampling.h")

INTEGRATOR = Enum("IntegratorKind", [
    ("PATH", "Path", "Path Tracing", "Unidirectional path tracing with next event estimation and MIS"),
    ("PSF_SMIS", "PsfSmis", "Path-Space Filtering (SMIS)",
     "Reuses the indirect light of nearby paths, weighted by stochastic MIS (West et al. 2020, eq. 17). "
     "Biased (no visibility in the weights, reused scattering), much less noise"),
    ("PSF_KELLER", "PsfKeller", "Path-Space Filtering (Keller)",
     "Keller et al. 2014: reuses nearby paths accepted by surface similarity. Biased"),
    ("PSF_SMIS_UNBIASED", "PsfSmisUnbiased", "Path-Space Filtering (SMIS, unbiased)",
     "Eq. 17 with exact visibility and scattering for every connection and density: unbiased but costly "
     "(one shadow ray per technique pair)"),
    ("PSF_PATH", "PsfPath", "Path-Space Filtering: no reuse",
     "The path tracer on the paths of the two-stage filtering pipeline (baseline)"),
])

PIXEL_FILTER = Enum("PixelFilterKind", [
    ("BLACKMAN_HARRIS", "BlackmanHarris", "Blackman-Harris", "Cycles' default: sharp, little ringing"),
    ("GAUSSIAN", "Gaussian", "Gaussian", "Softer"),
    ("BOX", "Box", "Box", "Each sample stays inside its pixel"),
], defined_in="film/pixel_filter.h")

SAMPLING_PATTERN = Enum("SamplingPattern", [
    ("STRATIFIED", "Stratified", "Stratified",
     "Owen-scrambled Sobol points for the pixel position, the lens and the first bounce's light and BSDF "
     "samples, so a pixel's samples spread evenly; independent random numbers after. Unbiased, less noise "
     "at the same samples, negligible cost"),
    ("RANDOM", "Random", "Random", "Independent random numbers for every decision (for comparisons)"),
])

SPECTRAL = Enum("SpectralSetting", [
    ("AUTO", "Auto", "Auto", "RGB when nothing in the scene has a spectrum (light or emission spectra, "
                             "measured metals, dispersion) or with photon planes, otherwise SMIS"),
    ("RGB", "Rgb", "RGB", "No spectral sampling: fastest, ignores spectra"),
    ("UNIFORM", "Uniform", "Uniform", "One wavelength per path, uniformly sampled"),
    ("SPECTRAL_IS", "SpectralIs", "Spectral IS", "One wavelength per path, importance sampled from the "
                                                 "observer response times the lights' spectra"),
    ("HERO", "Hero", "Hero Wavelength", "Wilkie et al. 2014: one importance-sampled hero, the others "
                                        "equally spaced, balance heuristic (eq. 19)"),
    ("SMIS", "Smis", "SMIS", "Every wavelength importance sampled (stratified), balance heuristic (eq. 21)"),
    ("SMIS_INDEPENDENT", "SmisIndependent", "SMIS (independent)", "SMIS with independent wavelengths"),
    ("BRUTE_FORCE", "BruteForce", "Brute Force (512)", "512 wavelengths per path: reference only"),
])

VOLUME_ESTIMATOR = Enum("VolumeEstimator", [
    ("PATH", "Path", "Path Tracing", "Distance sampling and next event estimation on every ray (the reference)"),
    ("PLANES_UNWEIGHTED", "PlanesUnweighted", "Photon Planes",
     "Each plane from one orientation (eq. 22): has the 1/|cos| singularity where camera rays run parallel "
     "to a plane"),
    ("PLANES_CMIS", "PlanesCmis", "Photon Planes, CMIS (Deng et al.)",
     "Deng et al. 2019's closed-form weighting over all plane orientations (eq. 26)"),
    ("PLANES_SMIS_COS", "PlanesSmisCos", "Photon Planes, SMIS (cosine)",
     "Stochastic MIS over n stratified orientations with cosine-only densities"),
    ("PLANES_SMIS_EXACT", "PlanesSmisExact", "Photon Planes, SMIS (exact)",
     "Stochastic MIS over n stratified orientations with the exact densities, including the plane width "
     "(eq. 25, 27): down-weights thin bright planes"),
])

DIRECT_LIGHT = Enum("DirectLightStrategy", [
    ("NEE", "Nee", "Next Event Estimation", "One light chosen by power, one point on it, MIS with BSDF sampling"),
    ("RIS", "Ris", "Resampled (RIS)",
     "Resampled importance sampling: M light candidates, one chosen by its unshadowed contribution, one "
     "shadow ray. Unbiased"),
    ("RESTIR", "Restir", "ReSTIR",
     "RIS, then reuse of reservoirs from neighbouring pixels and from the previous sample of the same pixel "
     "(Bitterli et al. 2020). Each sample is a whole-image pass"),
])

RESTIR_MIS = Enum("RestirMis", [
    ("SEED", "Seed", "Seed MIS", "One MIS weight for the selected sample: k pdf evaluations (ReSTIR supplement, "
                                 "Alg. 1)"),
    ("TALBOT", "Talbot", "Talbot MIS", "An MIS weight for every reused sample: k squared pdf evaluations (Alg. 2)"),
    ("NONE", "None", "None (1/M, biased)",
     "Plain normalisation by the candidate count: cheapest, biased (darker) where neighbours cannot "
     "produce the sample, e.g. near shadows"),
])


def _uses_planes(s):
    return s.volume_estimator.startswith("PLANES_")


def _seed(scene, s):
    seed = s.seed + (scene.frame_current if s.use_animated_seed else 0)
    return seed % 2 ** 31  # negative frames must still give a valid, distinct engine seed


def _threads(scene, s):
    if s.threads == 0 and scene.render.threads_mode == 'FIXED':
        return scene.render.threads
    return s.threads


_BOUNCES_WHY = ("Cycles' Light Paths > Max Bounces per type (beyond_bounce_limits): diffuse, glossy and "
                "transmission bounces, and passes through Transparent lobes (grey cut-outs are decided in the "
                "BVH and spend none). The defaults leave only max_bounces in force, as an unbiased render wants.")

SETTINGS = [
    # Sampling
    Setting("samples", "uint", 64, "Samples", "Number of samples (paths) per pixel", min=1, soft_max=4096,
            panel="sampling"),
    Setting("time_limit", "double", 0.0, "Time Limit",
            "Stop rendering after this many seconds, even if not all samples are done (0 means no limit)",
            why="seconds, 0 = none", min=0.0, subtype='TIME_ABSOLUTE', unit='TIME_ABSOLUTE', panel="sampling"),
    Setting("viewport_samples", "int", 32, "Viewport Samples",
            "Samples per pixel of the interactive viewport (Rendered shading); it refines progressively up to "
            "this and restarts after every edit", engine=False, min=1, soft_max=1024, panel="sampling"),
    Setting("viewport_resolution_divider", "int", 2, "Viewport Pixel Size",
            "Render the viewport at 1/N of its resolution and scale it up: N^2 times fewer paths per refinement",
            engine=False, min=1, max=8, panel="sampling"),
    Setting("seed", "uint", 0, "Seed", "Seed of the random numbers; different seeds give different noise patterns",
            min=0, panel="sampling", session=_seed),
    Setting("use_animated_seed", "bool", False, "Animated Seed",
            "Add the frame number to the seed, so that the noise pattern changes every frame", engine=False,
            panel="sampling", beside="seed"),
    Setting("sampling_pattern", SAMPLING_PATTERN, "STRATIFIED", "Pattern", "Random numbers of the pixel samples",
            why="the stratified prefix of every pixel sample's stream (core/stratified.h)", panel="sampling"),
    Setting("filter", PIXEL_FILTER, "BLACKMAN_HARRIS", "Pixel Filter",
            "Pixel reconstruction filter, importance-sampled as in Cycles (no extra cost)", prop="filter_type",
            panel="sampling"),
    Setting("filter_width", "float", 1.5, "Filter Width", "Pixel filter width in pixels (Cycles' default is 1.5)",
            min=1e-4, soft_min=0.01, soft_max=10.0, subtype='PIXEL', panel="sampling"),
    Setting("spectral", SPECTRAL, "AUTO", "Spectral", "Spectral rendering and its wavelength sampling "
            "(West et al. 2020, §5)",
            why="Spectral rendering (paper §5, spectral/wavelength_sampling.h). AUTO = RGB for scenes without "
                "spectral content, else SMIS.", panel="sampling"),
    Setting("wavelengths", "int", 4, "Wavelengths", "Wavelengths evaluated per path by Hero and SMIS",
            why="n for HERO / SMIS / SMIS_INDEPENDENT", min=1, max=64, panel="sampling",
            active=lambda s: s.spectral in {'AUTO', 'HERO', 'SMIS', 'SMIS_INDEPENDENT'}),

    # Light Paths
    Setting("integrator", INTEGRATOR, "PATH", "Integrator", "Light transport algorithm", panel="light_paths"),
    Setting("max_bounces", "int", 8, "Max Bounces",
            "Maximum number of bounces of a path, as Cycles' Max Bounces: 0 renders direct lighting only",
            why="Cycles' meaning: 0 = direct lighting only", min=0, soft_max=64, panel="light_paths"),
    Setting("hair_cycles_sampling", "bool", False, "Cycles Hair Sampling",
            "Sample the hair closures as Cycles 3.4 does. Principled Hair BSDF: each bounce's longitudinal sample "
            "from Cycles' per-bounce generator, whose numbers are correlated between bounces, so light bounced "
            "between strands comes out brighter than the converged image (about 20% after 8 bounces of sunlight). "
            "Hair BSDF: Cycles' sampler, which counts directions its own evaluation gives nothing. Matches Cycles' "
            "image, but biased. Off: independent samples of one consistent BSDF, unbiased",
            why="Cycles' correlated per-bounce LCG numbers for the Principled Hair's theta sample "
                "(lobes/principled_hair.h, ShaderRay::path_key) and its Hair BSDF sampler inconsistent with its "
                "eval (lobes/hair.h, kCyclesSampler): Cycles' look, biased; off by default.",
            panel="light_paths"),
    Setting("multiscatter_cycles_walk", "bool", False, "Cycles Multiscatter Evaluation",
            "Evaluate the Multiscatter GGX of the Glossy, Anisotropic, Glass and Principled BSDFs as Cycles 3.4 "
            "does: light samples by its stochastic random walk from the shallower direction (tinting each further "
            "bounce twice), BSDF samples by its walk from the view, weighted by its approximate density. Cycles' "
            "estimator is inconsistent, so its image depends on the lighting (a sun-lit anisotropic sphere up to "
            "5% darker than the walk's BSDF, rough glass up to 30%); this matches it, at the cost of a walk per "
            "evaluation. Off: one consistent BSDF (tabulated walk), deterministic and unbiased",
            why="Cycles' mf_eval / mf_sample / mf_pdf and their glass forms (lobes/multiscatter_walk.h, "
                "lobes/multi_glass_walk.h): Cycles' look, inconsistent; off by default.",
            panel="light_paths"),
    Setting("beckmann_cycles_sampling", "bool", False, "Cycles Anisotropic Beckmann Sampling",
            "Sample the Anisotropic BSDF's Beckmann distribution as Cycles 3.4 does: its visible normals drawn "
            "with the Roughness along the tangent in both directions, but weighted as if they came from the "
            "anisotropic distribution, so its image is biased where the two roughnesses differ (1.5% on a "
            "sphere of Roughness 0.4, Anisotropy -0.5). This matches Cycles' image, and chooses lights as Cycles "
            "3.4 does. Off: the anisotropic distribution's own samples, unbiased",
            why="Cycles' bsdf_microfacet_beckmann_sample (microfacet_sample_stretched with alpha_x twice) and its "
                "pdf (lobes/anisotropic.h, kCyclesSampler): Cycles' look, biased; off by default.",
            panel="light_paths"),
    Setting("mis_heuristic", MIS_HEURISTIC, "POWER", "MIS Heuristic",
            "How multiple importance sampling weights the sampling techniques", field="mis", panel="light_paths"),
    # Cycles' Light Paths > Max Bounces per type, Clamping and Caustics. Unlike Cycles' defaults (diffuse
    # and glossy 4, indirect clamp 10, Filter Glossy 1), ours leave the image unbiased: only Max Bounces
    # limits paths, nothing is clamped or blurred, caustics are on. A scene made for Cycles that sets
    # them renders with its own (`cycles`).
    Setting("diffuse_bounces", "int", 1024, "Diffuse",
            "Maximum number of diffuse reflection bounces, as Cycles' (bounded by Max Bounces); a lower limit "
            "darkens indirect diffuse light", why=_BOUNCES_WHY, field="max_diffuse_bounces", min=0, soft_max=64,
            panel="max_bounces", cycles="diffuse_bounces"),
    Setting("glossy_bounces", "int", 1024, "Glossy",
            "Maximum number of glossy reflection bounces, as Cycles' (bounded by Max Bounces)",
            field="max_glossy_bounces", min=0, soft_max=64, panel="max_bounces", cycles="glossy_bounces"),
    Setting("transmission_bounces", "int", 1024, "Transmission",
            "Maximum number of transmission bounces, as Cycles' (bounded by Max Bounces)",
            field="max_transmission_bounces", min=0, soft_max=64, panel="max_bounces", cycles="transmission_bounces"),
    Setting("transparent_bounces", "int", 1024, "Transparent",
            "Maximum number of passes through coloured transparency (Transparent BSDF) as Cycles'; grey alpha "
            "cut-outs are decided in the ray query and count none", field="max_transparent_bounces", min=0,
            soft_max=64, panel="max_bounces", cycles="transparent_max_bounces"),
    Setting("clamp_direct", "float", 0.0, "Direct Light",
            "Cycles' Clamp Direct: the largest value (sum of RGB) a sample's direct light may add, 0 = off. "
            "Clamping removes fireflies but biases (darkens) the image",
            why="Cycles' Clamp Direct (clamp_contribution): 0 = off. Clamping biases (darkens).", min=0.0,
            soft_max=100.0, panel="clamp", cycles="sample_clamp_direct"),
    Setting("clamp_indirect", "float", 0.0, "Indirect Light",
            "Cycles' Clamp Indirect: the largest value (sum of RGB) a sample's indirect light may add, 0 = off. "
            "Clamping removes fireflies but biases (darkens) the image", min=0.0, soft_max=100.0, panel="clamp",
            cycles="sample_clamp_indirect"),
    Setting("filter_glossy", "float", 0.0, "Filter Glossy",
            "Cycles' Filter Glossy: after diffuse or rough bounces, glossy surfaces are rendered rougher (by the "
            "path's smallest sampling density), 0 = off. Less noise from caustics, but the image is biased",
            why="Cycles' Filter Glossy (scene.cycles.blur_glossy; blur_glossy_lobes): 0 = off. On, a vertex reached "
                "by a path whose smallest BSDF sampling density so far is low (after a diffuse or rough bounce) "
                "raises its microfacet lobes' roughness. Biased by design (less noise from caustics).",
            min=0.0, soft_max=10.0, panel="caustics", cycles="blur_glossy"),
    Setting("caustics_reflective", "bool", True, "Reflective Caustics",
            "Cycles' Reflective Caustics: off, surfaces reached by diffuse bounces leave out their glossy "
            "reflection; less noise, but the image is biased (darker)",
            why="Cycles' Reflective / Refractive Caustics: off, a surface reached by a diffuse ray leaves out its "
                "glossy reflection / refraction lobes (lobe_is_caustic). Off biases (darkens) the image.",
            panel="caustics", cycles="caustics_reflective"),
    Setting("caustics_refractive", "bool", True, "Refractive Caustics",
            "Cycles' Refractive Caustics: off, surfaces reached by diffuse bounces leave out their refraction; "
            "less noise, but the image is biased (darker)", panel="caustics", cycles="caustics_refractive"),

    # Path-space filtering (integrators PSF_*)
    Setting("psf_radius_px", "float", 6.0, "Filter Radius",
            "Radius in screen pixels, projected to world space at each path's first non-specular vertex, within "
            "which paths share their indirect light. Larger reuses more (less noise, more blur); cost grows with "
            "the neighbours gathered", why="gather radius in screen pixels, projected to world at the vertex",
            min=0.1, soft_max=32.0, subtype='PIXEL', panel="psf"),
    Setting("psf_radius_alpha", "float", 2.0 / 3.0, "Radius Shrink",
            "Progressive shrink of the radius, r_i = r_0 (i+1)^((alpha-1)/2) as in progressive photon mapping: "
            "1 keeps it fixed, smaller shrinks faster", min=0.05, max=1.0, panel="psf"),
    Setting("psf_max_neighbors", "int", 24, "Max Neighbours",
            "Most paths combined per pixel (a random subset beyond this). The SMIS weights cost the square of "
            "this per set of gathered paths (see Shared Sets)",
            why="Techniques gathered per pixel (random subset beyond this). With shared technique sets "
                "(psf_block_size) the k^2 denominators are paid once per set, and 24 beat 16 at 2 s (3 seeds, two "
                "runs): psf_room SMAPE -7%, psf_glossy -2%; 32 helped the room more but raised psf_glossy's "
                "relMSE by 10%.", min=1, soft_max=128, panel="psf"),
    Setting("psf_light_samples", "int", 4, "Light Samples",
            "Light samples per iteration at each path's first non-specular vertex, whose direct light stays per "
            "pixel while the indirect light is shared (multi-sample MIS with the BSDF sample). More cost a shadow "
            "ray each",
            why="Light samples at each path's prefix endpoint x1 per iteration. The direct light there stays per "
                "pixel while the indirect light is shared, so it becomes the larger part of the error: at 8 "
                "iterations (seeds 1-3) 4 samples take psf_glossy's SMAPE from 0.074 to 0.053 and psf_room's MSE "
                "from 0.0020 to 0.0015, for 17% / 11% more time per iteration (8 samples: 0.047, +48%).",
            min=1, soft_max=16, panel="psf"),
    Setting("psf_extra_paths", "int", 4, "Extra Paths",
            "Most extra paths per iteration from a pixel's first non-specular vertex where the filter cannot "
            "share its path (sharp lobes, thin or curved glossy objects): in proportion to the weight its own path "
            "keeps in its estimate. 0 = off",
            why="Extra paths per iteration from x1 where the filter cannot share the pixel's suffix (sharp lobes, "
                "thin or curved glossy objects): up to this many, in proportion to the own suffix's weight in the "
                "pixel's estimate averaged over the past iterations; kept by the pixel (see "
                "path_space_filtering.cpp). 0 = off.", min=0, max=255, soft_max=16, panel="psf"),
    Setting("psf_block_size", "int", 2, "Shared Sets",
            "Side of the pixel blocks (1, 2 or 4) whose pixels share one set of gathered paths, when their first "
            "vertices are close: the SMIS denominators are computed once per block rather than once per pixel. "
            "1 = every pixel gathers on its own",
            why="Side of the pixel blocks whose pixels share one technique set in stage 2 (1, 2 or 4; other values "
                "round down): the grid query and eq. 17's denominators are computed once per block.",
            min=1, max=4, panel="psf"),
    Setting("psf_keller_normal_cos", "float", 0.9, "Keller Normal Cosine",
            "Keller et al. weighting: accept a neighbour only if the cosine between the shading normals is at "
            "least this", why="Keller et al. 2014 acceptance: normals within ~26 degrees", min=-1.0, max=1.0,
            panel="psf", show=lambda s: s.integrator == 'PSF_KELLER'),
    Setting("psf_keller_plane", "float", 0.1, "Keller Plane Distance",
            "Keller et al. weighting: accept a neighbour only if its distance to the query's tangent plane is at "
            "most this fraction of the radius", why="... and within 0.1 radius of the query's tangent plane",
            min=0.0, soft_max=1.0, panel="psf", show=lambda s: s.integrator == 'PSF_KELLER'),

    # Participating media (West et al. 2020, §6)
    Setting("volume_estimator", VOLUME_ESTIMATOR, "PATH", "Volume Estimator",
            "How single scattering in participating media is estimated (volume bounces = 0). The photon-plane "
            "estimators (West et al. 2020, Sec. 6) handle the camera rays' scattering of light from rectangular "
            "area lights in homogeneous media; everything else comes from the path tracer",
            why="Single scattering in media (West et al. 2020, §6): PATH (distance sampling + NEE) or photon "
                "planes.", panel="volumes"),
    Setting("photon_planes", "uint", 40960, "Photon Planes",
            "Photon planes traced per iteration (one iteration per camera sample); a fresh set each iteration, "
            "the iterations are averaged", why="planes per iteration (one iteration = one camera sample)",
            min=1, soft_max=1000000, panel="volumes", show=_uses_planes),
    Setting("plane_shadow_rays", "uint", 0, "Shadow Rays per Camera Ray",
            "About this many of a camera ray's plane crossings trace their shadow ray, chosen by their unshadowed "
            "contribution and reweighted (Russian roulette: unbiased); 0 traces one for every crossing",
            why="K > 0: of a camera ray's plane crossings in one medium segment, about K trace their shadow ray, "
                "each with probability q = min(1, K c / sum c) by its unshadowed contribution c and divided by q "
                "(Russian roulette on visibility: unbiased); 0 traces every crossing's shadow ray.",
            min=0, soft_max=1024, panel="volumes", show=_uses_planes),
    Setting("plane_surface_samples", "uint", 0, "Surface Samples per Plane Set",
            "Path-tracer samples per pixel that one plane set serves (surfaces, other lights, secondary rays), so "
            "surfaces converge at the path tracer's pace; 0 chooses it from the plane set's gathering cost",
            why="Path-tracer samples per pixel that one plane set serves: each iteration gathers the planes along "
                "one camera ray per pixel and averages this many path samples for everything else (surfaces, other "
                "lights, secondary rays), so surfaces are not held to the plane iterations' count. 0: chosen per "
                "scene from the plane set's gathering cost (photon_planes.cpp).",
            min=0, soft_max=64, panel="volumes", show=_uses_planes),
    Setting("plane_stratified", "bool", True, "Stratified Plane Sets",
            "Draw each plane set's random numbers stratified over the set (Owen-scrambled Sobol points: the planes "
            "cover each light, its directions and their lengths evenly) instead of independently; unbiased either way",
            why="The planes of one set stratified over the set (PlaneSequence, photon_plane_set.h): each plane alone "
                "is distributed as before, so the estimator stays unbiased, but the number of planes a camera ray "
                "crosses varies far less (the grain).", panel="volumes", show=_uses_planes),
    Setting("plane_min_crossings", "float", 3.0, "Min Crossings per Segment",
            "Camera-ray fog segments that a plane set crosses fewer times than this on average (short segments, "
            "regions few planes reach) take their plane lights' single scattering from the path tracer instead; "
            "unbiased either way, 0 leaves every segment to the planes",
            why="The segment partition (photon_planes.cpp): a pilot plane set, drawn once and independent of the "
                "iterations' sets, counts the crossings of each pixel's camera-ray segments (averaged over the "
                "pilot pixels within 3 of it with plane_pilot_stride 2, over 5x5 pixels with stride 1); segments "
                "below this count are estimated by the path tracer's single scattering for the plane lights and "
                "skipped by the gather. A fixed partition of every camera ray's segments: unbiased. "
                "3: at 15 s, 512x384, load 10-14, SMAPE 0.14 and 0.13 where every segment to the planes gave 0.24 "
                "and 0.20 (volume_spot, volume_planes; PATH 0.14, 0.12), relMSE about the same (README, "
                "docs/bench/planes2_*.md).",
            min=0.0, soft_max=16.0, panel="volumes", show=_uses_planes),
    Setting("plane_min_light_crossings", "float", 16.0, "Min Crossings per Light",
            "Of the segments the planes take, a plane light that the pilot plane set crosses there fewer times than "
            "this on average (but at all) leaves its single scattering on that segment to the path tracer; the other "
            "lights stay with the planes. Unbiased either way, 0 off; only in scenes of at most 32 lights",
            why="The per-light segment partition (photon_planes.cpp): the pilot's crossings of each pixel's segments "
                "counted per plane light (averaged as for plane_min_crossings: the pilot pixels within 3 with "
                "plane_pilot_stride 2, 5x5 pixels with stride 1); a light below this count on a segment is the path "
                "tracer's there (the media light choice then includes it), every other plane light the planes'. A fixed "
                "partition of every (segment, light) pair: unbiased. 16: at one plane set and 16 path samples per "
                "pixel (8 on volume_thin_hg), 512x384, SMAPE 0.116 -> 0.072 (volume_spot), 0.100 -> 0.068 "
                "(volume_planes), 0.166 -> 0.095 (volume_thin_hg), relMSE the same or lower (docs/bench/planes3.md).",
            min=0.0, soft_max=16.0, panel="volumes", show=_uses_planes),
    Setting("plane_pilot_stride", "uint", 2, "Pilot Stride",
            "The pilot plane set of the segment partitions counts crossings on every this-th pixel in x and y "
            "(1: every pixel); the pilot is a fixed cost of the first iteration. Unbiased either way",
            why="The pilot of the segment partitions (photon_planes.cpp) gathers along one camera ray of every "
                "stride-th pixel in x and y, and each pixel averages the pilot pixels within 3 of it (1: every "
                "pixel, within 2, as before). The pilot is part of the first iteration's fixed cost, which at a "
                "5 s budget leaves the path part fewer samples than PATH gets (docs/bench/planes4.md).",
            min=1, max=8, panel="volumes", show=_uses_planes),
    Setting("plane_crossing_cost", "float", 0.2, "Crossing Cost",
            "The automatic path samples per plane set (Surface Samples 0) count each camera-ray plane crossing as "
            "this many path samples of gathering cost; larger: more path samples per plane set. Unbiased either way",
            why="The cost model that chooses M (plane_surface_samples 0) and K (plane_path_pixel_samples 0): "
                "G = crossings per camera ray x this + 3 path samples per iteration, M = round(G) "
                "(photon_planes.cpp, gather_cost). 0.2 was measured on volume_spot at 512x384 from thread times; "
                "instruction counts later gave about 0.13 (docs/bench/planes5_where.md, docs/bench/planes6.md).",
            min=0.0, soft_max=2.0, panel="volumes", show=_uses_planes),
    Setting("plane_path_pixel_samples", "uint", 1, "Path Samples where no Plane Gathers",
            "Path samples per pass for the pixels whose camera rays the segment partitions leave wholly to the "
            "path tracer (they gather no planes and their pass is cheaper); 0 chooses it from the gathering cost "
            "(about the path tracer's samples per unit time there), 1 one like every pixel. Unbiased either way",
            why="A pixel whose camera-ray segments the (fixed, pilot-derived) partitions leave wholly to the path "
                "tracer gathers nothing: its pass costs its path sample only, a gathering pixel's the path sample "
                "and the gather. Such pixels take K path samples per pass (their value is the mean of their path "
                "samples; K depends on the partition only, fixed before the iterations: unbiased). 0: K = "
                "round(1 + G / M), G the gathering cost per camera ray in path samples that chooses M "
                "(plane_surface_samples), 2 where M is automatic. Default 1: at equal instructions K = 2 lowered "
                "volume_spot's SMAPE 2-4% (relMSE +2-7%) and raised volume_planes' SMAPE 3% and relMSE 15% "
                "(docs/bench/planes5_where.md).",
            min=0, soft_max=16, panel="volumes", show=_uses_planes),
    Setting("smis_planes", "int", 2, "SMIS Orientations",
            "n, the number of stratified plane orientations per SMIS realisation (eq. 27); with 2 the partner "
            "plane is perpendicular and only weighted", why="n: orientations per SMIS realisation (eq. 27)",
            min=1, max=64, panel="volumes", show=lambda s: s.volume_estimator.startswith("PLANES_SMIS")),

    # Many-light direct illumination (integrator PATH), at the camera path's first non-specular vertex
    Setting("direct_light", DIRECT_LIGHT, "NEE", "Direct Light",
            "How the path tracer samples the direct light at the first non-specular surface seen from the camera "
            "(deeper bounces always use next event estimation)",
            why="Many-light direct illumination at the camera path's first non-specular vertex (PATH only; deeper "
                "vertices keep NEE). RESTIR makes PATH a multi-stage integrator (integrators/restir.h).",
            panel="direct_light"),
    Setting("ris_candidates", "int", 16, "Candidates",
            "Light candidates per pixel and sample (M) for RIS and ReSTIR. More candidates follow the unshadowed "
            "contribution more closely, at the cost of one light sample and BSDF evaluation each (no shadow ray)",
            why="M: light candidates per pixel and iteration", min=1, soft_max=256, panel="direct_light",
            show=lambda s: s.direct_light != 'NEE'),
    Setting("restir_mis", RESTIR_MIS, "SEED", "Reuse MIS",
            "How reservoirs from different pixels are weighted against each other", panel="direct_light",
            show=lambda s: s.direct_light == 'RESTIR'),
    Setting("restir_neighbors", "int", 5, "Neighbours",
            "Pixels whose reservoirs are reused per pixel (k). The MIS weights cost k pdf evaluations with Seed "
            "MIS and k squared with Talbot MIS", why="k: spatial neighbours per pixel", min=0, soft_max=32,
            panel="direct_light", show=lambda s: s.direct_light == 'RESTIR'),
    Setting("restir_radius_px", "float", 3.0, "Neighbour Radius",
            "Neighbours are drawn uniformly from a disk of this radius around the pixel, among pixels whose "
            "surface is similar (normals, distance). Close neighbours share the visibility, so a few pixels work "
            "best (measured at 128 px: 3 beat 5); Bitterli et al. use 30 at 1920x1080",
            why="Neighbours drawn uniformly from this disk (screen pixels). Close neighbours share visibility: on "
                "scenes/many_lights.blend (128 px, k = 5, 64 spp) relMSE 0.0133 at 2 px, 0.0135 at 3, 0.0149 at 5 "
                "for the same time; 3 keeps a few more distinct pixels to draw k from.",
            min=1.0, soft_max=100.0, subtype='PIXEL', panel="direct_light", show=lambda s: s.direct_light == 'RESTIR'),
    Setting("restir_history_cap", "int", 0, "History Cap",
            "The previous sample's reservoir of the same pixel counts as at most this many times M candidates "
            "(the offline analogue of temporal reuse); 0 disables that reuse and makes every sample independent. "
            "The samples are averaged and a history correlates them: on the many-light scene it did not lower the "
            "error per sample and cost time, so it is off by default",
            why="The previous iteration's reservoir counts at most cap x M; 0 (the default) makes every iteration "
                "an independent ReSTIR estimate. Unlike real-time ReSTIR, the iterations are averaged, and the "
                "history correlates them: on scenes/many_lights.blend (128 px, 64 spp) cap 2 gave the same relMSE "
                "as cap 0 (0.0146-0.0148 vs 0.0147-0.0149) at ~10% more time per iteration, cap 8 a higher one "
                "(0.021 vs 0.015); cap 20 with a 30 px radius was 4x worse at 3 s.",
            min=0, soft_max=100, panel="direct_light", show=lambda s: s.direct_light == 'RESTIR'),
    Setting("restir_visibility_reuse", "bool", True, "Visibility Reuse",
            "Drop each pixel's initial sample when it is occluded (one shadow ray) before reuse, so neighbours "
            "share only visible samples. Off keeps occluded samples: then the MIS weights need no visibility and "
            "stay unbiased",
            why="occluded initial samples are dropped (Bitterli et al. Alg. 5, l. 7-9)", panel="direct_light",
            show=lambda s: s.direct_light == 'RESTIR'),
    Setting("restir_unbiased", "bool", True, "Unbiased",
            "Trace the visibility of the selected sample from each neighbour for the MIS weights, so neighbours "
            "that cannot see it get zero weight. Off skips those shadow rays: faster, but biased (darker) near "
            "shadows. Only matters with Visibility Reuse", why="visibility of every neighbour in the MIS pdfs",
            panel="direct_light", show=lambda s: s.direct_light == 'RESTIR',
            active=lambda s: s.restir_visibility_reuse and s.restir_mis != 'NONE'),

    # Performance
    Setting("threads", "int", 0, "Threads",
            "Number of render threads; 0 uses all cores, or Blender's fixed thread count when Threads Mode is "
            "Fixed (-t N on the command line)", why="0 = all cores", min=0, soft_max=256, panel="performance",
            session=_threads),

    # Set by the add-on from the scene and the view layer, not Blender properties of their own
    Setting("aux_passes", "bool", False, prop=None,
            why="Depth/Normal/Albedo/diagnostic passes (recorded at the camera path's first hit; a camera ray "
                "of their own only past a medium boundary or a holdout hole)"),
    Setting("aux_shading", "bool", True, prop=None, why="...of which Normal or Albedo (else the first hit's depth "
                                                        "is all they need)"),
    Setting("film_transparent", "bool", False, prop=None,
            why="Blender's Film > Transparent: the World seen by camera rays (directly or through transparent "
                "surfaces only) becomes alpha instead of colour; it still lights the scene (PathState)."),
    Setting("film_transparent_glass", "float", -1.0, prop=None,
            why="Cycles' Transparent Glass (with Film Transparent): a refraction through glass whose GGX alpha "
                "(roughness^2) is at most this keeps the path transparent, so the World behind glass becomes alpha "
                "too. Negative: off."),
    # Engine settings for tests and benchmarks only
    Setting("spectral_pixel_sequence", "bool", True, prop=None,
            why="Wavelength offsets of a pixel's samples from core/pixel_sequence.h (stratified over the samples) "
                "instead of independent random numbers; off only to measure what it brings."),
    Setting("spectral_wavelength", "float", 0.0, prop=None,
            why="> 0: PATH renders the spectral radiance at this one wavelength (nm, within [360, 830]) into every "
                "channel, with no wavelength sampling and no RGB response: the tests' reference, integrated against "
                "the observer by the test itself."),
    Setting("camera_volume_only", "bool", False, prop=None,
            why="Benchmarks of the volume estimators: render only the camera rays' single scattering (PATH: from "
                "every light; photon planes: from the rectangular lights they cover)."),
    Setting("glow_directions", "bool", True, prop=None,
            why="Tests and benchmarks: off, the path tracers continue from surfaces in fog by BSDF sampling alone, "
                "without the directions aimed at radius-0 lights there (integrators/glow_directions.h)."),
]

BY_KEY = {s.key: s for s in SETTINGS}
