// Measured spectral tables compiled into the engine (generated tables.cpp; sources and licences in
// spectral/data/SOURCES.md): CIE 1931 2-degree observer, CIE illuminants, metal complex IOR, glasses.
#pragma once

namespace smis::spectral::tables {

// Samples at lambda0 + i * step nm, i < count.
struct UniformTable {
    float lambda0, step;
    int count;
    const float* values;
};

struct MetalTable {  // complex IOR n + i k at non-uniform wavelengths (nm), increasing
    const char* name;
    int count;
    const float *lambda, *n, *k;
};

struct SellmeierGlass {  // n^2 = 1 + sum B_i l^2 / (l^2 - C_i), l in micrometres, C in um^2
    const char* name;
    float B[3], C[3];
};

extern const UniformTable cie_x, cie_y, cie_z;  // 360-830 nm, 1 nm
extern const UniformTable illum_D65, illum_A;   // 300-830 nm, 1 nm
extern const UniformTable illum_F2, illum_F10, illum_F11;  // 380-780 nm, 1 nm (CIE FL 1 nm dataset)
extern const MetalTable metals[];
extern const int metal_count;
extern const SellmeierGlass glasses[];
extern const int glass_count;

}  // namespace smis::spectral::tables
