"""Render presets in the Render Properties' Sampling header: common set-ups and the paper's
comparison set-ups. A preset sets only the properties it names; everything else stays as it was."""

import bpy
from bpy.props import EnumProperty

# name -> (label, what it is for, scene.smis values)
PRESETS = {
    "QUICK": ("Quick Preview", "16 samples, 4 bounces, RGB path tracing: a fast look at the scene",
              {"integrator": 'PATH', "direct_light": 'NEE', "samples": 16, "max_bounces": 4, "spectral": 'RGB',
               "volume_estimator": 'PATH', "viewport_samples": 16, "viewport_resolution_divider": 2}),
    "FINAL": ("Final", "1024 samples, 12 bounces, spectral rendering where the scene needs it",
              {"integrator": 'PATH', "direct_light": 'NEE', "samples": 1024, "max_bounces": 12, "spectral": 'AUTO',
               "volume_estimator": 'PATH', "viewport_samples": 64, "viewport_resolution_divider": 1}),
    "PAPER_PSF": ("Paper: Path-Space Filtering (Fig. 6)",
                  "Path-space filtering with SMIS weights at 8 paths per pixel, radius 6 px, 8 bounces (the "
                  "set-up of bench/psf_fig6.py; switch the integrator to PSF_KELLER or PSF_PATH to compare)",
                  {"integrator": 'PSF_SMIS', "samples": 8, "max_bounces": 8, "psf_radius_px": 6.0,
                   "psf_keller_normal_cos": 0.9, "psf_keller_plane": 0.1, "spectral": 'RGB'}),
    "PAPER_SPECTRAL": ("Paper: Spectral SMIS (Figs. 8-9)",
                       "Spectral path tracing with SMIS wavelength sampling, 4 wavelengths per path (compare "
                       "with HERO or SPECTRAL_IS at equal samples)",
                       {"integrator": 'PATH', "direct_light": 'NEE', "spectral": 'SMIS', "wavelengths": 4,
                        "volume_estimator": 'PATH'}),
    "PAPER_PLANES": ("Paper: Photon Planes (Fig. 11)",
                     "Single scattering in media by photon planes with SMIS over 2 plane orientations, the "
                     "default 40,960 planes per iteration (compare with PLANES_UNWEIGHTED, PLANES_CMIS)",
                     {"integrator": 'PATH', "volume_estimator": 'PLANES_SMIS_COS', "smis_planes": 2,
                      "photon_planes": 40960, "spectral": 'RGB'}),
    "PAPER_RESTIR": ("Paper: ReSTIR MIS (supplement)",
                     "Direct light only with ReSTIR and the seed MIS (Alg. 1), M 16, k 5 (compare with "
                     "TALBOT or NONE)",
                     {"integrator": 'PATH', "direct_light": 'RESTIR', "restir_mis": 'SEED', "max_bounces": 0,
                      "ris_candidates": 16, "restir_neighbors": 5, "spectral": 'RGB', "volume_estimator": 'PATH'}),
}


def apply(settings, name):
    """Set scene.smis properties from preset `name`."""
    for key, value in PRESETS[name][2].items():
        setattr(settings, key, value)


class SMIS_OT_apply_preset(bpy.types.Operator):
    """Set the SMIS render settings of a preset"""
    bl_idname = "smis.apply_preset"
    bl_label = "Apply SMIS Preset"
    bl_options = {'REGISTER', 'UNDO'}

    preset: EnumProperty(items=[(k, v[0], v[1]) for k, v in PRESETS.items()], name="Preset")

    @classmethod
    def description(cls, context, properties):
        return PRESETS[properties.preset][1]

    def execute(self, context):
        apply(context.scene.smis, self.preset)
        return {'FINISHED'}


class SMIS_MT_presets(bpy.types.Menu):
    bl_label = "SMIS Presets"

    def draw(self, context):
        for key, (label, _, _) in PRESETS.items():
            self.layout.operator(SMIS_OT_apply_preset.bl_idname, text=label).preset = key


classes = (SMIS_OT_apply_preset, SMIS_MT_presets)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
