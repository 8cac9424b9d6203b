#include "shading/sky_nishita.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "spectral/color.h"

namespace smis {

namespace {

// The model's constants (Blender's intern/sky, so the tables agree with Cycles'): scale heights,
// Mie scattering and anisotropy, the radii of the Earth and of the top of the atmosphere.
constexpr float kRayleighScale = 8e3f, kMieScale = 1.2e3f;
constexpr float kMieCoeff = 2e-5f, kMieG = 0.76f;
constexpr float kMieExtinction = 1.11f * kMieCoeff;  // Mie extinction = scattering / albedo 0.9
constexpr float kEarthRadius = 6360e3f, kAtmosphereRadius = 6420e3f;
constexpr int kSteps = 32;  // segments of a view ray
// 21 wavelengths, 380-780 nm every 20 nm.
constexpr int kWavelengths = 21;
constexpr float kLambda0 = 380.0f, kLambdaStep = 20.0f;
// Solar irradiance at the top of the atmosphere (W m^-2 nm^-1), Rayleigh scattering and ozone
// absorption coefficients (m^-1) at those wavelengths: the data Blender's model uses.
constexpr float kIrradiance[kWavelengths] = {
    1.45756830f, 1.56596306f, 1.65148449f, 1.71496243f, 1.75797984f, 1.78256408f, 1.79095108f,
    1.78541550f, 1.76815555f, 1.74122070f, 1.70647127f, 1.66556087f, 1.61993437f, 1.57083597f,
    1.51932335f, 1.46628495f, 1.41245853f, 1.35844962f, 1.30474914f, 1.25174963f, 1.19975999f};
constexpr float kRayleigh[kWavelengths] = {
    5.424820088e-5f, 4.418549867e-5f, 3.635151910e-5f, 3.017929012e-5f, 2.526320227e-5f, 2.130859311e-5f,
    1.809838025e-5f, 1.547057129e-5f, 1.330284977e-5f, 1.150184784e-5f, 9.995574300e-6f, 8.727999736e-6f,
    7.655137010e-6f, 6.742172038e-6f, 5.961341258e-6f, 5.290345981e-6f, 4.711156876e-6f, 4.209104811e-6f,
    3.772183813e-6f, 3.390512555e-6f, 3.055915317e-6f};
constexpr float kOzone[kWavelengths] = {
    3.251268499e-9f, 5.853953650e-9f, 1.977191155e-8f, 7.309568763e-8f, 2.008456151e-7f, 4.038395810e-7f,
    6.355133591e-7f, 9.670704118e-7f, 1.547974004e-6f, 2.090386472e-6f, 2.461280562e-6f, 2.735512995e-6f,
    2.151258631e-6f, 1.590518408e-6f, 1.123561980e-6f, 7.352755149e-7f, 4.645013036e-7f, 3.309607992e-7f,
    2.251261229e-7f, 1.487912927e-7f, 1.682862336e-7f};
// Optical depth towards the sun by 8-point Gauss-Laguerre quadrature (the densities fall off about
// exponentially along the ray), nodes scaled so the last lies inside the atmosphere and weights with
// the exp(x) factor folded in, as in Blender.
constexpr int kQuadrature = 8;
constexpr float kQuadratureNodes[kQuadrature] = {0.006811185292f, 0.03614807107f, 0.09004346519f, 0.1706680068f,
                                                 0.2818362161f,   0.4303406404f,  0.6296271457f,  0.9145252695f};
constexpr float kQuadratureWeights[kQuadrature] = {0.01750893642f, 0.04135477391f, 0.06678839063f, 0.09507698807f,
                                                   0.1283416365f,  0.1707430204f,  0.2327233347f,  0.3562490486f};

Vec3 geographical_to_direction(float lat, float lon) {
    return {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
}

// Densities relative to sea level: air and dust fall off exponentially, ozone is a tent between 10
// and 40 km peaking at 25 km.
Vec3 densities(float height) {
    float ozone = 0.0f;
    if (height >= 10000.0f && height < 25000.0f) ozone = height / 15000.0f - 2.0f / 3.0f;
    else if (height >= 25000.0f && height < 40000.0f) ozone = 8.0f / 3.0f - height / 15000.0f;
    return {std::exp(-height / kRayleighScale), std::exp(-height / kMieScale), ozone};
}

float phase_rayleigh(float mu) { return 3.0f / (16.0f * kPi) * (1.0f + mu * mu); }
// Cornette-Shanks.
float phase_mie(float mu) {
    const float g2 = kMieG * kMieG;
    return 3.0f * (1.0f - g2) * (1.0f + mu * mu) /
           (8.0f * kPi * (2.0f + g2) * std::pow(1.0f + g2 - 2.0f * kMieG * mu, 1.5f));
}

// Whether the ray from p along d meets the Earth (only downward rays can).
bool hits_earth(const Vec3& p, const Vec3& d) {
    if (d.z >= 0.0f) return false;
    float b = 2.0f * dot(d, p), c = dot(p, p) - kEarthRadius * kEarthRadius;
    return b * b - 4.0f * c >= 0.0f;
}

// Distance from p (inside the atmosphere) along d to its top.
float to_atmosphere_top(const Vec3& p, const Vec3& d) {
    float b = 2.0f * dot(d, p), c = dot(p, p) - kAtmosphereRadius * kAtmosphereRadius;
    return 0.5f * (-b + std::sqrt(b * b - 4.0f * c));
}

// Optical depth factors (air, dust, ozone: multiply by their coefficients) from p to the top along d.
Vec3 optical_depth(const Vec3& p, const Vec3& d) {
    const float length = to_atmosphere_top(p, d);
    Vec3 depth(0.0f);
    for (int i = 0; i < kQuadrature; ++i) {
        Vec3 q = p + d * (kQuadratureNodes[i] * length);
        depth += densities(std::sqrt(dot(q, q)) - kEarthRadius) * kQuadratureWeights[i];
    }
    return depth * length;
}

Vec3 spectrum_to_xyz(const float* s) {
    Vec3 xyz(0.0f);
    for (int i = 0; i < kWavelengths; ++i) xyz += spectral::cie_xyz(kLambda0 + kLambdaStep * i) * s[i];
    return xyz * kLambdaStep;
}

// Single scattering of sunlight into the view ray from `origin` along `dir` (spectral radiance):
// midpoint rule over kSteps segments, each segment's light attenuated from the sun to it and from it
// to the origin.
void inscattering(const Vec3& dir, const Vec3& sun, const Vec3& origin, const Vec3& scale, float* spectrum) {
    const float seg = to_atmosphere_top(origin, dir) / kSteps;
    const float mu = dot(dir, sun);
    const float ph_r = phase_rayleigh(mu), ph_m = phase_mie(mu);
    std::fill(spectrum, spectrum + kWavelengths, 0.0f);
    Vec3 depth(0.0f);
    Vec3 p = origin + dir * (0.5f * seg);
    for (int i = 0; i < kSteps; ++i, p += dir * seg) {
        const Vec3 density = scale * densities(std::sqrt(dot(p, p)) - kEarthRadius);
        depth += density * seg;  // up to the segment's far end, as Blender accumulates it
        if (hits_earth(p, sun)) continue;
        const Vec3 total = depth + scale * optical_depth(p, sun);
        for (int w = 0; w < kWavelengths; ++w) {
            float tau = total.x * kRayleigh[w] + total.y * kMieExtinction + total.z * kOzone[w];
            float scattering = ph_r * density.x * kRayleigh[w] + ph_m * density.y * kMieCoeff;
            spectrum[w] += std::exp(-tau) * scattering * kIrradiance[w] * seg;
        }
    }
}

// The sun's radiance seen along dir (attenuated by air and dust only, as in Blender), XYZ.
Vec3 sun_xyz(const Vec3& dir, const Vec3& origin, float air, float dust, float solid_angle) {
    const Vec3 depth = optical_depth(origin, dir);
    float s[kWavelengths];
    for (int w = 0; w < kWavelengths; ++w)
        s[w] = kIrradiance[w] * std::exp(-(kRayleigh[w] * depth.x * air + kMieExtinction * depth.y * dust)) / solid_angle;
    return spectrum_to_xyz(s);
}

}  // namespace

NishitaSky::NishitaSky(const NishitaParams& p) {
    // Cycles' compile step: the altitude kept in [1 m, 60 km) (below, numerical trouble; above,
    // space), the disc at least 0.0005 rad wide, the rotation taken into [0, 2 pi) and mirrored.
    const float altitude = clampf(p.altitude, 1.0f, 59999.0f);
    elevation_ = p.sun_elevation;
    diameter_ = std::max(p.sun_size, 0.0005f);
    intensity_ = p.sun_intensity;
    disc_ = p.sun_disc;
    float rot = std::fmod(p.sun_rotation, 2.0f * kPi);
    if (rot < 0.0f) rot += 2.0f * kPi;
    rotation_ = 2.0f * kPi - rot;
    const Vec3 origin(0.0f, 0.0f, kEarthRadius + altitude);
    const Vec3 scale(p.air_density, p.dust_density, p.ozone_density);

    // The sky table, in the sun's frame (sun at azimuth 0): rows at latitude (pi/2 + half a row)
    // (y / height)^2, more of them near the horizon; columns over the azimuth from -pi, the second
    // half mirroring the first (the sky is symmetric about the sun's meridian).
    table_.assign(size_t(kWidth) * kHeight, Vec3(0.0f));
    const Vec3 sun = geographical_to_direction(elevation_, 0.0f);
    const float half_row = 0.25f * kPi / kHeight;
    tbb::parallel_for(tbb::blocked_range<int>(0, kHeight), [&](const tbb::blocked_range<int>& rows) {
        float spectrum[kWavelengths];
        for (int y = rows.begin(); y < rows.end(); ++y) {
            const float lat = (0.5f * kPi + half_row) * sqr(float(y) / kHeight);
            for (int x = 0; x < kWidth / 2; ++x) {
                const float lon = (2.0f * kPi / kWidth) * x - kPi;
                inscattering(geographical_to_direction(lat, lon), sun, origin, scale, spectrum);
                const Vec3 xyz = spectrum_to_xyz(spectrum);
                table_[size_t(y) * kWidth + x] = table_[size_t(y) * kWidth + (kWidth - 1 - x)] = xyz;
            }
        }
    });

    // The disc: the sun's radiance at its lowest and highest point (clamped to the horizon).
    const float half = 0.5f * diameter_;
    const float solid_angle = 2.0f * kPi * (1.0f - std::cos(half));
    sun_bottom_ = sun_xyz(geographical_to_direction(std::max(elevation_ - half, 0.0f), 0.0f), origin, p.air_density,
                          p.dust_density, solid_angle);
    sun_top_ = sun_xyz(geographical_to_direction(std::max(elevation_ + half, 0.0f), 0.0f), origin, p.air_density,
                       p.dust_density, solid_angle);
    sun_dir_ = geographical_to_direction(elevation_, rotation_ + 0.5f * kPi);
    has_sun_ = disc_ && elevation_ + half > 0.0f && intensity_ > 0.0f;
}

Vec3 NishitaSky::lookup(float u, float v) const {
    const float fx = u * kWidth - 0.5f, fy = v * kHeight - 0.5f;
    const float x0f = std::floor(fx), y0f = std::floor(fy);
    const float tx = fx - x0f, ty = fy - y0f;
    auto at = [&](float xf, float yf) {
        int x = int(std::clamp(xf, 0.0f, float(kWidth - 1)));
        int y = int(std::clamp(yf, 0.0f, float(kHeight - 1)));
        return table_[size_t(y) * kWidth + x];
    };
    return (at(x0f, y0f) * (1.0f - tx) + at(x0f + 1.0f, y0f) * tx) * (1.0f - ty) +
           (at(x0f, y0f + 1.0f) * (1.0f - tx) + at(x0f + 1.0f, y0f + 1.0f) * tx) * ty;
}

Color NishitaSky::radiance(const Vec3& dir) const {
    // Table column: the azimuth (Cycles' atan2(x, y)) turned by the sun's rotation.
    auto column = [&] {
        float u = (std::atan2(dir.x, dir.y) + kPi + rotation_) / (2.0f * kPi);
        return u > 1.0f ? u - 1.0f : u;
    };
    Vec3 xyz(0.0f);
    if (dir.z >= 0.0f) {
        const float half = 0.5f * diameter_;
        const float dir_elevation = 0.5f * kPi - std::acos(clampf(dir.z, -1.0f, 1.0f));
        // The angle to the sun's centre, accurate for tiny angles.
        const float angle = 2.0f * std::atan2(length(dir - sun_dir_), length(dir + sun_dir_));
        if (disc_ && angle < half) {
            if (elevation_ + half > 0.0f) {
                // Linear between the disc's lowest and highest point (from the horizon when the
                // disc is cut by it); limb darkening with coefficient 0.6.
                const float t = elevation_ - half > 0.0f ? (dir_elevation - elevation_) / diameter_ + 0.5f
                                                         : dir_elevation / (elevation_ + half);
                xyz = (sun_bottom_ + (sun_top_ - sun_bottom_) * t) * intensity_;
            }
            xyz = xyz * (1.0f - 0.6f * (1.0f - std::sqrt(std::max(0.0f, 1.0f - sqr(angle / half)))));
        } else {
            xyz = lookup(column(), std::sqrt(std::max(dir_elevation / (0.5f * kPi), 0.0f)));
        }
    } else if (dir.z >= -0.4f) {
        // The ground: the horizon row fading to black at dir.z = -0.4.
        const float fade = 1.0f + 2.5f * dir.z;
        xyz = lookup(column(), -0.5f) * (fade * fade * fade);
    }
    return vmax(spectral::xyz_to_rgb(xyz), Color(0.0f));
}

}  // namespace smis
