// The two checks every lobe test file runs on its lobes (closure_lobes_test.cpp,
// multiscatter_glass_test.cpp, multiscatter_aniso_test.cpp), written once on top of stats.h:
//  * expect_sampling_matches_pdf(): chi-square of lobe_sample() against lobe_pdf() from one wo, at the
//    Sidak-corrected level of the file's family of cases, and at least a tenth of the samples valid;
//  * expect_sample_agrees_with_eval(): over random wo, every valid sample's value and pdf are what
//    lobe_eval() and lobe_pdf() return for its direction, a unit direction on the side it says
//    (reflection or transmission), plus a file's own condition on the sample.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "core/rng.h"
#include "core/sampling.h"
#include "scene/bsdf.h"
#include "stats.h"

namespace smis::lobe_checks {

inline Point2 rand2(Rng& rng) { return {rng.next_float(), rng.next_float()}; }

// Cycles' alpha_x, alpha_y of the Anisotropic BSDF (svm/closure.h), clamped to [1e-4, 1] as its
// multiscatter setup does.
inline std::pair<float, float> cycles_alphas(float roughness, float anisotropy) {
    float alpha = roughness * roughness;
    float ax = anisotropy < 0.0f ? alpha / (1.0f + anisotropy) : alpha * (1.0f - anisotropy);
    float ay = anisotropy < 0.0f ? alpha * (1.0f + anisotropy) : alpha / (1.0f - anisotropy);
    return {clampf(ax, 1e-4f, 1.0f), clampf(ay, 1e-4f, 1.0f)};
}

// The direction of polar cosine cos_theta and azimuth phi.
inline Vec3 dir_from_cos(float cos_theta, float phi) {
    float s = safe_sqrt(1.0f - cos_theta * cos_theta);
    return normalize(Vec3(s * std::cos(phi), s * std::sin(phi), cos_theta));
}

// A lobe under test, and one chi-square case: a lobe seen from wo.
struct NamedLobe {
    std::string name;
    Lobe lobe;
};
struct Chi2Case {
    std::string name;
    Lobe lobe;
    Vec3 wo;
};
// Every lobe from every view (polar cosine, azimuth), named <lobe>_cos<cosine>.
inline std::vector<Chi2Case> chi2_cases_of(const std::vector<NamedLobe>& lobes,
                                           std::initializer_list<std::pair<float, float>> views) {
    std::vector<Chi2Case> cases;
    for (const NamedLobe& nl : lobes)
        for (auto [cos_theta, phi] : views)
            cases.push_back({nl.name + "_cos" + stats::num(cos_theta), nl.lobe, dir_from_cos(cos_theta, phi)});
    return cases;
}

// One sample of `lobe` from wo as the chi-square test histograms it.
inline stats::DirSample dir_sample(const Lobe& lobe, const Vec3& wo, Rng& rng) {
    BsdfSample s = lobe_sample(lobe, wo, rand2(rng), rng.next_float());
    if (!s.valid()) return stats::DirSample::invalid();
    if (s.delta) return stats::DirSample::delta();
    return stats::DirSample::valid(s.wi, s.pdf);
}

// Chi-square of the lobe's sampling from wo against its pdf, one of `num_cases` such tests whose family
// may raise a false alarm with probability `family_significance`.
inline void expect_sampling_matches_pdf(const std::string& name, const Lobe& lobe, const Vec3& wo, uint64_t seed,
                                        uint64_t samples, int num_cases, double family_significance = 0.01) {
    stats::Chi2Options opt;
    opt.seed = seed;
    stats::Chi2Result r = stats::chi2_test_directions([&](Rng& rng) { return dir_sample(lobe, wo, rng); },
                                                      [&](const Vec3& wi) { return double(lobe_pdf(lobe, wo, wi)); },
                                                      samples, opt);
    double alpha = stats::sidak_significance(family_significance, num_cases);
    std::printf("[chi2] %-40s %s\n", name.c_str(), r.summary().c_str());
    EXPECT_TRUE(r.passes(alpha)) << name << ": " << r.summary() << "\n" << r.residual_map();
    EXPECT_GT(r.n_valid, samples / 10) << name;
}

// 20000 samples from wo uniform on the sphere (its upper half unless two_sided): none mismatched, more
// than 5000 valid. also(wo, s) is the file's own condition on a valid sample.
template <class Also>
void expect_sample_agrees_with_eval(const std::string& name, const Lobe& lobe, Rng& rng, bool two_sided, Also&& also) {
    int valid = 0, mismatches = 0;
    for (int i = 0; i < 20000; ++i) {
        Vec3 wo = sample_uniform_sphere(rand2(rng));
        if (!two_sided) wo.z = std::fabs(wo.z);
        BsdfSample s = lobe_sample(lobe, wo, rand2(rng), rng.next_float());
        if (!s.valid()) continue;
        ++valid;
        Color e = lobe_eval(lobe, wo, s.wi);
        float p = lobe_pdf(lobe, wo, s.wi);
        using stats::close_rel;
        bool ok = !s.delta && close_rel(s.value.x, e.x) && close_rel(s.value.y, e.y) && close_rel(s.value.z, e.z) &&
                  close_rel(s.pdf, p) && std::fabs(length(s.wi) - 1.0f) < 1e-4f &&
                  s.transmission == (s.wi.z * wo.z < 0.0f) && also(wo, s);
        mismatches += !ok;
    }
    EXPECT_EQ(mismatches, 0) << name;
    EXPECT_GT(valid, 5000) << name;
}
inline void expect_sample_agrees_with_eval(const std::string& name, const Lobe& lobe, Rng& rng, bool two_sided) {
    expect_sample_agrees_with_eval(name, lobe, rng, two_sided, [](const Vec3&, const BsdfSample&) { return true; });
}

// The number of factors c in t (per channel a power of c): the sampled weight of Cycles' walk estimators
// (one colour per further bounce); -1 (and a failed expectation) when t is not one.
inline int power_of(const Color& t, const Color& c) {
    float k = std::log(t.z) / std::log(c.z);
    EXPECT_NEAR(k, std::round(k), 1e-3f) << t.z;
    EXPECT_NEAR(t.x, std::pow(c.x, std::round(k)), 1e-4f);
    EXPECT_NEAR(t.y, std::pow(c.y, std::round(k)), 1e-4f);
    return std::fabs(k - std::round(k)) < 1e-3f ? int(std::round(k)) : -1;
}

}  // namespace smis::lobe_checks
