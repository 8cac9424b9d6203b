// The Sky Texture's Nishita model as Blender 3.4 has it (Cycles' default sky type): single
// scattering by air (Rayleigh) and dust (Mie) with ozone absorption in a spherical atmosphere
// (Nishita et al. 1993, "Display of the Earth taking into account atmospheric scattering"), seen from
// `altitude` metres above sea level, with the sun's disc. Like Blender, the sky is tabulated once per
// node (512 x 128 XYZ cells over azimuth and elevation, rows denser towards the horizon) and read
// with bilinear filtering; the disc is interpolated between the sun's radiance at its lowest and
// highest point, with limb darkening. Only the constants and the table layout follow Blender
// (intern/sky/source/sky_nishita.cpp, Cycles' svm/sky.h), so images match Cycles'.
#pragma once
#include <vector>

#include "core/math.h"

namespace smis {

struct NishitaParams {
    float sun_elevation = 0.2618f;  // radians above the horizon
    float sun_rotation = 0.0f;      // the node's Sun Rotation (radians, as the user sets it)
    bool sun_disc = true;
    float sun_size = 0.009512f;     // angular diameter (radians)
    float sun_intensity = 1.0f;
    float altitude = 0.0f;          // metres
    float air_density = 1.0f, dust_density = 1.0f, ozone_density = 1.0f;
};

class NishitaSky {
public:
    // Precomputes the table (about 10^8 flops, spread over the TBB threads).
    explicit NishitaSky(const NishitaParams& p);

    // The sky's radiance towards direction dir (unit, world axes, +z up) in scene-linear RGB, as
    // Cycles' sky_radiance_nishita + xyz_to_rgb_clamped compute it.
    Color radiance(const Vec3& dir) const;

    // The sun's disc (for sampling it on its own): direction towards its centre and half the
    // angular diameter; has_sun() is false without a disc or with the disc below the horizon.
    bool has_sun() const { return has_sun_; }
    const Vec3& sun_direction() const { return sun_dir_; }
    float sun_half_angle() const { return 0.5f * diameter_; }

    static constexpr int kWidth = 512, kHeight = 128;
    // The table's XYZ at cell (x, y) (y = 0 the horizon row), for tests.
    Vec3 cell(int x, int y) const { return table_[size_t(y) * kWidth + x]; }
    // The two XYZ values the disc is interpolated between (the sun's lowest and highest point).
    const Vec3& sun_bottom() const { return sun_bottom_; }
    const Vec3& sun_top() const { return sun_top_; }

private:
    Vec3 lookup(float u, float v) const;  // bilinear, clamped to the edges (Cycles' EXTEND)

    std::vector<Vec3> table_;
    Vec3 sun_bottom_, sun_top_, sun_dir_;
    float elevation_, rotation_, diameter_, intensity_;  // rotation_: Cycles' 2 pi - wrapped rotation
    bool disc_, has_sun_;
};

}  // namespace smis
