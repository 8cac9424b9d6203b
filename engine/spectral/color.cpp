#include "spectral/color.h"


namespace smis::spectral {

float sample_table(const tables::UniformTable& t, float lambda) {
    float x = (lambda - t.lambda0) / t.step;
    if (!(x >= 0.0f) || x > float(t.count - 1)) return 0.0f;
    int i = std::min(int(x), t.count - 2);
    float f = x - float(i);
    return t.values[i] * (1.0f - f) + t.values[i + 1] * f;
}

Vec3 cie_xyz(float lambda) {
    return {sample_table(tables::cie_x, lambda), sample_table(tables::cie_y, lambda), sample_table(tables::cie_z, lambda)};
}

Color xyz_to_rgb(const Vec3& v) {
    return {3.2404542f * v.x - 1.5371385f * v.y - 0.4985314f * v.z,
            -0.9692660f * v.x + 1.8760108f * v.y + 0.0415560f * v.z,
            0.0556434f * v.x - 0.2040259f * v.y + 1.0572252f * v.z};
}

Vec3 rgb_to_xyz(const Color& c) {
    return {0.4124564f * c.x + 0.3575761f * c.y + 0.1804375f * c.z,
            0.2126729f * c.x + 0.7151522f * c.y + 0.0721750f * c.z,
            0.0193339f * c.x + 0.1191920f * c.y + 0.9503041f * c.z};
}

Color rgb_response(float lambda) { return xyz_to_rgb(cie_xyz(lambda)) * float(1.0 / kCieYIntegral); }

}  // namespace smis::spectral
