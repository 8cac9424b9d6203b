// Spectral modes against a reference over independent renders (spectral_media_test,
// spectral_subsurface_test): per-pixel z-tests (Sidak-corrected) and the image mean per channel.
#pragma once
#include <cstdio>

#include "test_scenes.h"

namespace smis::testing {

inline RenderSettings spectral_settings(const char* mode) {
    RenderSettings st;
    st.max_bounces = 6;
    st.spectral = setting_value<SpectralSetting>(mode);
    return st;
}

// Per-pixel and image-mean agreement of `got` with the reference `ref` (renders named `label` and
// `reference` in the messages).
inline void expect_agreement(const PixelStats& got, const PixelStats& ref, const char* label, const char* reference) {
    double worst_z = 0.0;
    const double acc = accepted_fraction(got, ref), p_mean = smallest_channel_p_value(got, ref, &worst_z);
    std::printf("%-6s against %-7s: pixels agreeing %.4f, image means R %.5f G %.5f B %.5f (reference %.5f %.5f "
                "%.5f), worst image-mean z %+.2f\n",
                label, reference, acc, got.channel_image[0].mean(), got.channel_image[1].mean(),
                got.channel_image[2].mean(), ref.channel_image[0].mean(), ref.channel_image[1].mean(),
                ref.channel_image[2].mean(), worst_z);
    EXPECT_GE(acc, 0.99) << label;
    EXPECT_GT(p_mean, 1e-3) << label;
}

// The same for each of the spectral modes `modes` against the mode `reference` (the path tracer),
// over independent renders.
inline void expect_agreement(const std::shared_ptr<Scene>& scene, std::initializer_list<const char*> modes,
                             const char* reference, int renders, uint32_t spp) {
    PixelStats ref = across_renders(scene, spectral_settings(reference), renders, spp, 7000, true);
    EXPECT_GT(ref.image.mean(), 0.02);  // lit: the test can fail
    for (const char* mode : modes)
        expect_agreement(across_renders(scene, spectral_settings(mode), renders, spp, 8000, true), ref, mode, reference);
}

}  // namespace smis::testing
