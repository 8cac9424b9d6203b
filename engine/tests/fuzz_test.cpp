// A bounded-time fuzzer of the scene-building API: random (often invalid) meshes, instances,
// materials, lights, world and camera, committed and rendered tiny with a random integrator. The
// engine must reject bad input with std::invalid_argument (never crash) and every pixel must be
// finite. Deterministic given SMIS_FUZZ_SEED (default 1); time budget SMIS_FUZZ_SECONDS (default 20),
// count limit SMIS_FUZZ_ITERATIONS (default unlimited).
#include <gtest/gtest.h>

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <csignal>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <memory>
#include <stdexcept>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/rng.h"
#include "render/session.h"
#include "scene/scene.h"
#include "test_scenes.h"

using namespace smis;

namespace {

// Spectral settings; the last entry of each list is invalid on purpose.
const char* const kSpectra[] = {"RGB", "BLACKBODY", "D65", "A", "F2", "F10", "F11", "F99"};
const char* const kMetals[] = {"NONE", "Au", "Ag", "Cu", "Al", "Xx"};
const char* const kDispersions[] = {"NONE", "ABBE", "N-BK7", "SF11", "Glass?"};
const char* const kSpectralModes[] = {"AUTO", "RGB", "UNIFORM", "SPECTRAL_IS", "HERO", "SMIS", "SMIS_INDEPENDENT",
                                      "BRUTE_FORCE"};

double env_double(const char* name, double fallback) {
    const char* v = std::getenv(name);
    if (!v || !*v) return fallback;
    char* end = nullptr;
    double d = std::strtod(v, &end);
    return end != v ? d : fallback;
}

// Random values biased towards the pathological.
struct Fuzz {
    Rng rng;
    explicit Fuzz(uint64_t seed, uint64_t iteration) : rng(seed, iteration * 0x9E3779B97F4A7C15ull) {}
    uint32_t u32() { return rng.next_u32(); }
    int range(int lo, int hi) { return lo + int(u32() % uint32_t(hi - lo + 1)); }  // inclusive
    float uniform(float lo, float hi) { return lo + (hi - lo) * rng.next_float(); }
    bool chance(float p) { return rng.next_float() < p; }
    // A float: mostly reasonable, sometimes special.
    float value(float lo, float hi, float p_special = 0.1f) {
        if (!chance(p_special)) return uniform(lo, hi);
        switch (range(0, 11)) {
            case 0: return std::numeric_limits<float>::quiet_NaN();
            case 1: return std::numeric_limits<float>::infinity();
            case 2: return -std::numeric_limits<float>::infinity();
            case 3: return 1e30f;
            case 4: return -1e30f;
            case 5: return std::numeric_limits<float>::denorm_min() * float(range(1, 1000));
            case 6: return -std::numeric_limits<float>::denorm_min();
            case 7: return 0.0f;
            case 8: return -0.0f;
            case 9: return std::numeric_limits<float>::max();
            case 10: return 1e-30f;
            default: return -1.0f;
        }
    }
    Color color(float hi, float p_special = 0.1f) {
        return Color(value(0.0f, hi, p_special), value(0.0f, hi, p_special), value(0.0f, hi, p_special));
    }
    // A transform: identity, translation, rotation-scale, singular, mirrored or non-finite.
    Transform transform(float p_special) {
        Transform t;
        int kind = range(0, 9);
        if (kind <= 2) {  // translation
            for (int r = 0; r < 3; ++r) t.m[r][3] = uniform(-3.0f, 3.0f);
        } else if (kind <= 6) {  // general random matrix
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 4; ++c) t.m[r][c] = uniform(c == 3 ? -3.0f : -1.5f, c == 3 ? 3.0f : 1.5f);
        } else if (kind == 7) {  // rank-deficient
            for (int c = 0; c < 4; ++c) t.m[2][c] = t.m[0][c] * uniform(-2.0f, 2.0f);
            t.m[0][3] = uniform(-1.0f, 1.0f);
        } else if (kind == 8) {  // mirror + scale
            t.m[0][0] = -uniform(0.1f, 3.0f), t.m[1][1] = uniform(0.1f, 3.0f), t.m[2][2] = uniform(0.1f, 3.0f);
        }
        if (chance(p_special)) t.m[range(0, 2)][range(0, 3)] = value(0, 0, 1.0f);
        return t;
    }
};

// A crash (assertion inside Embree, segfault) cannot be reported by GoogleTest: a signal handler
// prints the seed and iteration being fuzzed, then lets the signal kill the process as usual.
char g_crash_note[160] = "fuzz: crashed before the first iteration\n";
extern "C" void on_fatal_signal(int sig) {
    ssize_t ignored = write(STDERR_FILENO, g_crash_note, std::strlen(g_crash_note));
    (void)ignored;
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}
const int kFatalSignals[] = {SIGABRT, SIGSEGV, SIGFPE, SIGBUS, SIGILL, SIGTERM, SIGINT};

struct Totals {
    uint64_t scenes = 0, rejected = 0, nan_caught = 0, dropped_triangles = 0, pixels = 0;
    uint64_t scenes_with_nan = 0, first_nan_iteration = UINT64_MAX;
};

// Builds, commits and renders one random scene; returns false on a failed assertion.
void fuzz_one(Fuzz& f, Totals& totals, uint64_t seed, uint64_t iteration) {
    auto scene = std::make_shared<Scene>();
    Scene& s = *scene;
    auto reject = [&](auto&& fn) {
        try {
            fn();
        } catch (const std::invalid_argument&) {
            ++totals.rejected;
        }
    };

    // Materials.
    std::vector<uint32_t> mats{0};
    int nm = f.range(0, 5);
    for (int i = 0; i < nm; ++i) {
        Material m;
        int nl = f.range(0, Bsdf::kMaxLobes + 2);  // more lobes than a Bsdf holds, sometimes
        for (int k = 0; k < nl; ++k) {
            Lobe l;
            l.kind = LobeKind(f.range(0, 6));
            l.fresnel = FresnelMode(f.range(0, 2));
            l.weight = f.chance(0.1f) ? Color(f.value(-2.0f, 2.0f, 1.0f)) : f.color(1.2f);
            l.f0 = f.color(1.0f);
            l.alpha = f.chance(0.3f) ? 0.0f : f.value(-0.1f, 1.2f);
            l.eta = f.chance(0.2f) ? 1.0f : f.value(0.2f, 5.0f);
            m.lobes.push_back(l);
        }
        if (f.chance(0.3f)) m.emission = f.color(20.0f, 0.2f);
        if (f.chance(0.3f)) {  // spectral content, sometimes with names the engine must refuse
            m.spectral.emission_spectrum = kSpectra[f.range(0, 7)];
            m.spectral.emission_temperature = f.value(50.0f, 20000.0f);
            m.spectral.metal = kMetals[f.range(0, 5)];
            m.spectral.dispersion = kDispersions[f.range(0, 4)];
            m.spectral.abbe = f.value(-5.0f, 200.0f);
        }
        try {
            mats.push_back(s.add_material(m));
        } catch (const std::invalid_argument&) {
            ++totals.rejected;
        }
    }

    // Meshes and instances.
    int nmesh = f.range(0, 4);
    for (int i = 0; i < nmesh; ++i) {
        int nv = f.range(0, 50), nt = f.range(0, 40);
        float scale = f.chance(0.1f) ? f.value(1e-5f, 1e5f, 0.5f) : 2.0f;
        std::vector<float> v(3 * size_t(nv));
        for (float& x : v) x = f.chance(0.03f) ? f.value(0, 0, 1.0f) : f.uniform(-scale, scale);
        std::vector<int32_t> t(3 * size_t(nt));
        for (int32_t& x : t) {
            int r = f.range(0, 39);
            x = r == 0 ? -f.range(1, 1000) : r == 1 ? nv + f.range(0, 5) : r == 2 ? INT32_MIN : r == 3 ? INT32_MAX
                : nv > 0 ? f.range(0, nv - 1) : 0;
        }
        std::vector<float> n;
        if (f.chance(0.5f)) {
            n.resize(9 * size_t(nt));
            int mode = f.range(0, 3);  // 0 random, 1 zero, 2 NaN-laden, 3 unit +z
            for (size_t k = 0; k < n.size(); ++k)
                n[k] = mode == 0 ? f.uniform(-1, 1) : mode == 1 ? 0.0f : mode == 2 ? f.value(-1, 1, 0.5f)
                                                                      : (k % 3 == 2 ? 1.0f : 0.0f);
        }
        std::vector<int32_t> mi;
        if (f.chance(0.5f)) {
            mi.resize(size_t(nt));
            for (int32_t& x : mi) x = f.range(-2, int(mats.size()) + 2);
        }
        std::vector<uint32_t> slots;
        int ns = f.range(0, 4);
        for (int k = 0; k < ns; ++k) slots.push_back(f.chance(0.1f) ? f.u32() : mats[f.range(0, int(mats.size()) - 1)]);
        uint32_t mesh = s.add_mesh(v.data(), size_t(nv), t.data(), size_t(nt), n.empty() ? nullptr : n.data(),
                                   mi.empty() ? nullptr : mi.data(), slots);
        totals.dropped_triangles += s.mesh_dropped(mesh);
        int ni = f.range(0, 3);
        for (int k = 0; k < ni; ++k) {
            Transform xf = f.transform(0.1f);
            // Non-finite or (numerically) singular: must be rejected. Exactly singular and denormal
            // determinants count; the engine may reject more (ill-conditioned) transforms.
            float det = xf.determinant3();
            bool bad = !xf.is_finite() || !(std::fabs(det) >= std::numeric_limits<float>::min());
            bool threw = false;
            try {
                s.add_instance(f.chance(0.05f) ? mesh + 1000 : mesh, xf);
            } catch (const std::invalid_argument&) {
                threw = true;
                ++totals.rejected;
            }
            if (bad) {
                EXPECT_TRUE(threw) << "singular/non-finite instance transform accepted; seed " << seed
                                   << " iteration " << iteration;
            }
        }
    }

    // Lights.
    static const char* const kTypes[] = {"AREA", "POINT", "SPOT", "SUN", "BOGUS"};
    static const char* const kShapes[] = {"SQUARE", "RECTANGLE", "DISK", "ELLIPSE", "TRIANGLE"};
    int nlights = f.range(0, 4);
    for (int i = 0; i < nlights; ++i) {
        LightDesc d;
        d.type = kTypes[f.chance(0.05f) ? 4 : f.range(0, 3)];
        d.shape = kShapes[f.range(0, 4)];
        d.to_world = f.transform(0.05f);
        d.color = f.color(1.0f, 0.05f);
        d.power = f.value(0.0f, 1000.0f);
        d.strength = f.value(0.0f, 20.0f);
        d.size = f.value(0.0f, 2.0f);
        d.size_y = f.value(0.0f, 2.0f);
        d.radius = f.chance(0.3f) ? 0.0f : f.value(0.0f, 0.5f);
        d.spot_size = f.value(0.0f, 3.5f);
        d.spot_blend = f.value(0.0f, 1.2f);
        d.angle = f.chance(0.3f) ? 0.0f : f.value(0.0f, 3.5f);
        d.visible_to_camera = f.chance(0.8f);
        if (f.chance(0.3f)) d.spectrum = kSpectra[f.range(0, 7)], d.temperature = f.value(50.0f, 20000.0f);
        reject([&] { s.add_light(d); });
    }
    if (f.chance(0.5f)) s.set_world(f.color(2.0f, 0.15f));

    // Camera.
    CameraDesc c;
    c.width = c.height = 8;
    c.to_world = f.transform(0.1f);
    c.to_world.m[2][3] += f.uniform(2.0f, 8.0f);  // usually outside the geometry, looking down
    c.orthographic = f.chance(0.2f);
    c.lens = f.value(5.0f, 100.0f, 0.05f);
    c.ortho_scale = f.value(0.5f, 10.0f, 0.05f);
    c.clip_start = f.value(1e-4f, 0.5f, 0.05f);
    c.clip_end = f.value(10.0f, 1e4f, 0.05f);
    c.shift_x = f.value(-0.5f, 0.5f, 0.05f);
    c.shift_y = f.value(-0.5f, 0.5f, 0.05f);
    if (f.chance(0.05f)) c.pixel_aspect_x = f.value(0.5f, 2.0f, 0.5f);
    if (f.chance(0.05f)) c.sensor_width = f.value(1.0f, 50.0f, 0.5f);
    if (f.chance(0.1f)) c.sensor_fit = f.chance(0.5f) ? "HORIZONTAL" : "VERTICAL";
    if (f.chance(0.05f)) c.width = f.range(-1, 1);
    if (f.chance(0.1f)) {  // a render border
        c.border[0] = f.range(0, 8), c.border[1] = f.range(0, 8), c.border[2] = f.range(0, 9), c.border[3] = f.range(0, 9);
    }
    try {
        s.set_camera(c);
    } catch (const std::invalid_argument&) {
        ++totals.rejected;
        CameraDesc sane;
        sane.width = sane.height = 8;
        sane.to_world.m[2][3] = 6.0f;
        s.set_camera(sane);
    }

    s.commit();

    RenderSettings rs;
    rs.samples = uint32_t(f.range(1, 2));
    rs.max_bounces = f.range(0, 6);
    const std::string& integrator = smis::testing::all_integrators()[f.range(0, int(smis::testing::all_integrators().size()) - 1)];
    smis::testing::select_integrator(rs, integrator);
    rs.mis = f.chance(0.5f) ? MisHeuristic::Power : MisHeuristic::Balance;
    rs.seed = f.u32();
    rs.spectral = setting_value<SpectralSetting>(kSpectralModes[f.range(0, 7)]);
    rs.wavelengths = f.range(1, 8);
    rs.threads = 1;
    // Settings the engine does not support together (e.g. photon planes with a spectral mode) must be
    // refused with a clear error, which counts as a rejected input.
    std::unique_ptr<RenderSession> made;
    try {
        made = std::make_unique<RenderSession>(scene, rs);
    } catch (const std::invalid_argument&) {
        ++totals.rejected;
        return;
    }
    RenderSession& session = *made;
    session.run();
    ASSERT_TRUE(session.error().empty()) << session.error() << "; seed " << seed << " iteration " << iteration;
    std::vector<float> px = session.pixels();
    for (size_t i = 0; i < px.size(); ++i)
        ASSERT_TRUE(std::isfinite(px[i])) << "non-finite pixel value " << px[i] << " at " << i << " with "
                                          << integrator << "; seed " << seed << " iteration " << iteration;
    totals.pixels += px.size() / 4;
    uint64_t nan = session.progress().nan_caught;
    totals.nan_caught += nan;
    if (nan > 0) {
        ++totals.scenes_with_nan;
        if (totals.first_nan_iteration == UINT64_MAX) totals.first_nan_iteration = iteration;
    }
    ++totals.scenes;
}

}  // namespace

TEST(Fuzz, RandomScenesRenderFinite) {
    const double budget = env_double("SMIS_FUZZ_SECONDS", 20.0);
    const uint64_t seed = uint64_t(env_double("SMIS_FUZZ_SEED", 1.0));
    const double max_iterations = env_double("SMIS_FUZZ_ITERATIONS", 0.0);  // 0 = until the budget is spent
    std::printf("fuzz: seed %llu, budget %.1f s\n", static_cast<unsigned long long>(seed), budget);
    Totals totals;
    using Handler = void (*)(int);
    Handler previous[std::size(kFatalSignals)];
    for (size_t i = 0; i < std::size(kFatalSignals); ++i) previous[i] = std::signal(kFatalSignals[i], on_fatal_signal);
    // Watchdog: a scene that renders for longer than SMIS_FUZZ_HANG_SECONDS (default 10) is a hang;
    // report the seed and iteration and abort, rather than letting CI time out without a clue.
    const double hang_seconds = env_double("SMIS_FUZZ_HANG_SECONDS", 10.0);
    std::atomic<int64_t> scene_started_ns{0};
    std::atomic<bool> done{false};
    std::thread watchdog([&] {
        while (!done.load()) {
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
            int64_t t0 = scene_started_ns.load();
            int64_t now = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
            if (t0 != 0 && double(now - t0) * 1e-9 > hang_seconds) {
                std::fprintf(stderr, "\nfuzz: HANG (scene took more than %.0f s)", hang_seconds);
                on_fatal_signal(SIGABRT);
            }
        }
    });
    auto start = std::chrono::steady_clock::now();
    uint64_t it = 0;
    for (;; ++it) {
        double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (elapsed >= budget) break;
        if (max_iterations > 0 && double(it) >= max_iterations) break;
        std::snprintf(g_crash_note, sizeof g_crash_note,
                      "\nfuzz: CRASH at seed %llu iteration %llu (reproduce: SMIS_FUZZ_SEED=%llu SMIS_FUZZ_ITERATIONS=%llu)\n",
                      static_cast<unsigned long long>(seed), static_cast<unsigned long long>(it),
                      static_cast<unsigned long long>(seed), static_cast<unsigned long long>(it + 1));
        SCOPED_TRACE("fuzz seed " + std::to_string(seed) + " iteration " + std::to_string(it));
        Fuzz f(seed, it);  // each iteration has its own stream: reproducible in isolation
        scene_started_ns.store(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count());
        try {
            fuzz_one(f, totals, seed, it);
        } catch (const std::exception& e) {
            ADD_FAILURE() << "unexpected exception " << e.what() << "; seed " << seed << " iteration " << it;
        }
        if (::testing::Test::HasFailure()) {
            std::printf("fuzz: FAILED at seed %llu iteration %llu (rerun with SMIS_FUZZ_SEED=%llu)\n",
                        static_cast<unsigned long long>(seed), static_cast<unsigned long long>(it),
                        static_cast<unsigned long long>(seed));
            break;
        }
    }
    done.store(true);
    watchdog.join();
    for (size_t i = 0; i < std::size(kFatalSignals); ++i) std::signal(kFatalSignals[i], previous[i]);
    double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("fuzz: %llu scenes, %llu rejected inputs, %llu nan caught (%llu dropped triangles, %.1f s, %.0f scenes/s)\n",
                static_cast<unsigned long long>(totals.scenes), static_cast<unsigned long long>(totals.rejected),
                static_cast<unsigned long long>(totals.nan_caught),
                static_cast<unsigned long long>(totals.dropped_triangles), elapsed, totals.scenes / std::max(elapsed, 1e-9));
    std::fflush(stdout);
    if (totals.scenes_with_nan > 0)
        std::printf("fuzz: %llu scenes had non-finite samples caught by the film guard (first: iteration %llu)\n",
                    static_cast<unsigned long long>(totals.scenes_with_nan),
                    static_cast<unsigned long long>(totals.first_nan_iteration));
    EXPECT_GT(totals.scenes, 0u);
}
