"""Spectral rendering settings on lights (`light.smis`) and materials (`material.smis`).

They only matter when the render is spectral (`scene.smis.spectral`, AUTO picks SMIS as soon
as one of them is set). Strength units stay Blender's: a spectrum is normalised so that its
luminance equals that of the RGB light it replaces (the light's colour contributes its
luminance, the spectrum the chromaticity), so switching a white light of 100 W to F10 keeps
its brightness and changes its colour.
"""

import bpy
from bpy.props import EnumProperty, FloatProperty, PointerProperty

SPECTRA = [
    ('RGB', "RGB", "The light colour, upsampled to a smooth spectrum (Jakob & Hanika 2019)"),
    ('BLACKBODY', "Blackbody", "Planck's law at the temperature below"),
    ('D65', "D65", "CIE standard illuminant D65 (daylight)"),
    ('A', "A", "CIE standard illuminant A (incandescent)"),
    ('F2', "F2", "CIE fluorescent FL2 (cool white)"),
    ('F10', "F10", "CIE fluorescent FL10 (narrow-band, spiky)"),
    ('F11', "F11", "CIE fluorescent FL11 (narrow-band, spiky)"),
]

METALS = [
    ('NONE', "None", "The Glossy / Principled colour and Fresnel as in RGB rendering"),
    ('Au', "Gold", "Measured complex IOR of gold"),
    ('Ag', "Silver", "Measured complex IOR of silver"),
    ('Cu', "Copper", "Measured complex IOR of copper"),
    ('Al', "Aluminium", "Measured complex IOR of aluminium"),
]

GLASSES = ["N-BK7", "N-BAF10", "N-FK51A", "N-LASF9", "F2", "N-SF5", "SF5", "N-SF10", "SF10",
           "N-SF11", "SF11", "LITHOSIL-Q", "fused_silica_Malitson1965"]
DISPERSION = ([('NONE', "None", "The IOR of the Glass / Principled node at every wavelength"),
               ('ABBE', "Abbe Number", "Cauchy law through the node's IOR (as n_d) and the Abbe "
                                       "number below")]
              + [(g, g.replace("_", " "), "Sellmeier coefficients of %s (SCHOTT / "
                  "refractiveindex.info); the node's IOR is ignored" % g) for g in GLASSES])


def _spectrum(name, description):
    return EnumProperty(name=name, description=description, items=SPECTRA, default='RGB')


def _temperature(description):
    return FloatProperty(name="Temperature", description=description, default=6500.0, min=100.0,
                         soft_min=800.0, soft_max=12000.0, max=1e6)


class SMISLightSettings(bpy.types.PropertyGroup):
    spectrum: _spectrum("Spectrum", "Emission spectrum in spectral rendering, at the luminance "
                                    "the RGB light would have")
    temperature: _temperature("Blackbody temperature (Blender 3.4 lights have none of their own)")


class SMISMaterialSettings(bpy.types.PropertyGroup):
    emission_spectrum: _spectrum("Emission Spectrum", "Spectrum of the material's emission in "
                                 "spectral rendering, at the luminance of its RGB emission")
    emission_temperature: _temperature("Blackbody temperature of the emission")
    metal: EnumProperty(
        name="Metal",
        description="Measured conductor for the Glossy BSDF and the metallic part of the "
                    "Principled BSDF (its colour still multiplies: keep it white)",
        items=METALS, default='NONE',
    )
    dispersion: EnumProperty(
        name="Dispersion",
        description="Wavelength-dependent IOR of sharp Glass / Principled transmission",
        items=DISPERSION, default='NONE',
    )
    abbe: FloatProperty(
        name="Abbe Number",
        description="V_d = (n_d - 1) / (n_F - n_C): smaller disperses more (crown glass ~60, "
                    "flint ~30)",
        default=40.0, min=1.0, max=1000.0, soft_min=10.0, soft_max=100.0,
    )


def light_spectral(light):
    """The spectral keys of a light dict."""
    s = light.smis
    return {"spectrum": s.spectrum, "temperature": float(s.temperature)}


def material_spectral(material):
    """The spectral keys of a material dict."""
    s = material.smis
    return {"emission_spectrum": s.emission_spectrum,
            "emission_temperature": float(s.emission_temperature),
            "metal": s.metal, "dispersion": s.dispersion, "abbe": float(s.abbe)}


classes = (SMISLightSettings, SMISMaterialSettings)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Light.smis = PointerProperty(type=SMISLightSettings, name="SMIS Light Settings")
    bpy.types.Material.smis = PointerProperty(type=SMISMaterialSettings,
                                              name="SMIS Material Settings")


def unregister():
    del bpy.types.Material.smis
    del bpy.types.Light.smis
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
