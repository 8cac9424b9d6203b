// Microbenchmark of the procedural texture nodes (shading/procedural_noise.h, procedural_cells.h):
// nanoseconds per call of each texture, per variant and dimension, on one thread.
//
// Build and run (from the repository root; the target is not part of the default build):
//   cmake --build build --target texture_speed
//   build/engine/texture_speed [CSV_PATH] [--quick] [--filter SUBSTRING]
// It prints a table and writes CSV (texture,variant,dims,ns_per_call) to CSV_PATH, by default
// bench/results/texture_speed.csv in the source tree. --quick measures for a tenth of the time;
// --filter keeps the rows whose "texture variant" contains SUBSTRING.
//
// Method: a fixed pool of 4096 pseudo-random inputs (coordinates in [-20, 20], so cells and lattice
// points vary from call to call as on a real surface) is evaluated round-robin; each row is timed
// over about 40 ms of this thread's CPU time (so time slices given to other processes do not count)
// and the fastest of 5 repetitions is kept, which filters out most interference on a shared
// machine. Results are summed into a checksum so that no call is optimised away. The numbers include
// the call through std::function (a few ns), which matters only for the cheapest textures.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "shading/procedural_cells.h"
#include "shading/procedural_noise.h"

#ifndef TEXTURE_SPEED_CSV
#define TEXTURE_SPEED_CSV "bench/results/texture_speed.csv"
#endif

using namespace smis;
using namespace smis::shading;

namespace {

struct Input {
    Vec3 co;
    float w;
};

std::vector<Input> make_inputs(size_t n) {
    std::vector<Input> in(n);
    uint64_t s = 0x9E3779B97F4A7C15ull;
    auto next = [&s]() {  // xorshift64*, mapped to [-20, 20]
        s ^= s >> 12, s ^= s << 25, s ^= s >> 27;
        uint32_t r = static_cast<uint32_t>((s * 0x2545F4914F6CDD1Dull) >> 40);  // 24 bits
        return -20.0f + 40.0f * (static_cast<float>(r) / 16777216.0f);
    };
    for (Input& i : in) {
        float x = next(), y = next(), z = next();
        i.co = Vec3(x, y, z);
        i.w = next();
    }
    return in;
}

struct Row {
    std::string texture, variant;
    int dims;
    std::function<float(const Input&)> f;
    double ns = 0.0;
};

volatile float g_sink;

// CPU time of this thread in seconds: time while other processes hold the core does not count.
double thread_seconds() {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double time_row(const Row& row, const std::vector<Input>& in, double seconds) {
    // Calibrate the batch size so one repetition lasts about `seconds`.
    size_t batch = in.size();
    double best = 1e30;
    float sum = 0.0f;
    for (size_t i = 0; i < in.size(); ++i) sum += row.f(in[i]);  // warm-up
    double t0 = thread_seconds();
    for (size_t i = 0; i < in.size(); ++i) sum += row.f(in[i]);
    double first = thread_seconds() - t0;
    size_t calls = std::max<size_t>(batch, static_cast<size_t>(seconds / std::max(first, 1e-9) * batch));
    for (int rep = 0; rep < 5; ++rep) {
        double t = thread_seconds();
        for (size_t k = 0, i = 0; k < calls; ++k) {
            sum += row.f(in[i]);
            if (++i == in.size()) i = 0;
        }
        double dt = thread_seconds() - t;
        best = std::min(best, dt * 1e9 / static_cast<double>(calls));
    }
    g_sink = sum;
    return best;
}

const char* feature_name(VoronoiFeature f) {
    switch (f) {
        case VoronoiFeature::F1: return "F1";
        case VoronoiFeature::F2: return "F2";
        case VoronoiFeature::SmoothF1: return "SmoothF1";
        case VoronoiFeature::DistanceToEdge: return "DistanceToEdge";
        case VoronoiFeature::NSphereRadius: return "NSphereRadius";
    }
    return "?";
}

const char* metric_name(VoronoiMetric m) {
    switch (m) {
        case VoronoiMetric::Euclidean: return "Euclidean";
        case VoronoiMetric::Manhattan: return "Manhattan";
        case VoronoiMetric::Chebychev: return "Chebychev";
        case VoronoiMetric::Minkowski: return "Minkowski";
    }
    return "?";
}

std::vector<Row> make_rows() {
    std::vector<Row> rows;
    for (int d = 1; d <= 4; ++d) {
        rows.push_back({"noise", "detail4 fac", d, [d](const Input& i) {
                            return noise_texture(d, i.co, i.w, 5.0f, 4.0f, 0.5f, 0.0f, false).fac;
                        }});
        rows.push_back({"noise", "detail2.5 color distortion1", d, [d](const Input& i) {
                            TextureOut t = noise_texture(d, i.co, i.w, 5.0f, 2.5f, 0.5f, 1.0f, true);
                            return t.fac + t.color.y + t.color.z;
                        }});
    }
    const std::pair<MusgraveType, const char*> types[] = {
        {MusgraveType::Fbm, "fBM"},
        {MusgraveType::Multifractal, "Multifractal"},
        {MusgraveType::HybridMultifractal, "Hybrid"},
        {MusgraveType::RidgedMultifractal, "Ridged"},
        {MusgraveType::HeteroTerrain, "Hetero"},
    };
    for (const auto& [type, name] : types)
        for (int d = 1; d <= 4; ++d)
            rows.push_back({"musgrave", std::string(name) + " detail4", d, [d, type = type](const Input& i) {
                                return musgrave_texture(d, type, i.co, i.w, 5.0f, 4.0f, 2.0f, 2.0f, 1.0f, 1.0f);
                            }});
    const VoronoiFeature features[] = {VoronoiFeature::F1, VoronoiFeature::F2, VoronoiFeature::SmoothF1,
                                       VoronoiFeature::DistanceToEdge, VoronoiFeature::NSphereRadius};
    for (VoronoiFeature f : features)
        for (int d = 1; d <= 4; ++d)
            rows.push_back({"voronoi", std::string(feature_name(f)) + " Euclidean", d, [d, f](const Input& i) {
                                VoronoiOut v = voronoi_texture(d, f, VoronoiMetric::Euclidean, i.co, i.w, 5.0f,
                                                               1.0f, 1.0f, 1.0f);
                                return v.distance + v.color.x + v.position.y + v.w + v.radius;
                            }});
    const VoronoiMetric metrics[] = {VoronoiMetric::Manhattan, VoronoiMetric::Chebychev, VoronoiMetric::Minkowski};
    for (VoronoiMetric m : metrics)
        for (int d = 2; d <= 4; ++d)
            rows.push_back({"voronoi", std::string("F1 ") + metric_name(m), d, [d, m](const Input& i) {
                                VoronoiOut v = voronoi_texture(d, VoronoiFeature::F1, m, i.co, i.w, 5.0f, 1.0f,
                                                               1.5f, 1.0f);
                                return v.distance + v.color.x + v.position.y + v.w;
                            }});
    for (int d = 1; d <= 4; ++d)
        rows.push_back({"white_noise", "fac+color", d, [d](const Input& i) {
                            TextureOut t = white_noise_texture(d, i.co, i.w);
                            return t.fac + t.color.y;
                        }});
    rows.push_back({"wave", "bands X sine", 3, [](const Input& i) {
                        return wave_texture(WaveType::Bands, WaveDirection::X, WaveProfile::Sine, i.co, 5.0f, 0.0f,
                                            2.0f, 1.0f, 0.5f, 0.0f)
                            .fac;
                    }});
    rows.push_back({"wave", "rings spherical saw distortion detail2", 3, [](const Input& i) {
                        return wave_texture(WaveType::Rings, WaveDirection::Spherical, WaveProfile::Saw, i.co, 5.0f,
                                            2.0f, 2.0f, 1.0f, 0.5f, 0.0f)
                            .fac;
                    }});
    rows.push_back({"magic", "depth2", 3, [](const Input& i) { return magic_texture(2, i.co, 5.0f, 1.0f).fac; }});
    rows.push_back({"magic", "depth10", 3, [](const Input& i) { return magic_texture(10, i.co, 5.0f, 1.0f).fac; }});
    rows.push_back({"checker", "", 3, [](const Input& i) {
                        return checker_texture(i.co, Color(0.8f), Color(0.2f), 5.0f).color.x;
                    }});
    rows.push_back({"gradient", "Linear", 3, [](const Input& i) {
                        return gradient_texture(GradientType::Linear, i.co).fac;
                    }});
    rows.push_back({"gradient", "Spherical", 3, [](const Input& i) {
                        return gradient_texture(GradientType::Spherical, i.co).fac;
                    }});
    rows.push_back({"gradient", "Radial", 3, [](const Input& i) {
                        return gradient_texture(GradientType::Radial, i.co).fac;
                    }});
    rows.push_back({"brick", "", 3, [](const Input& i) {
                        BrickOut b = brick_texture(i.co, Color(0.8f), Color(0.2f), Color(0.0f), 5.0f, 0.02f, 0.1f,
                                                   0.0f, 0.5f, 0.25f, 0.5f, 2, 1.0f, 2);
                        return b.fac + b.color.x;
                    }});
    return rows;
}

}  // namespace

int main(int argc, char** argv) {
    std::string csv_path = TEXTURE_SPEED_CSV, filter;
    double seconds = 0.04;
    for (int a = 1; a < argc; ++a) {
        if (std::strcmp(argv[a], "--quick") == 0) seconds = 0.004;
        else if (std::strcmp(argv[a], "--filter") == 0 && a + 1 < argc) filter = argv[++a];
        else csv_path = argv[a];
    }
    const std::vector<Input> inputs = make_inputs(4096);
    std::vector<Row> rows = make_rows();
    std::printf("%-12s %-40s %4s %12s\n", "texture", "variant", "dims", "ns/call");
    std::vector<Row*> done;
    for (Row& r : rows) {
        if (!filter.empty() && (r.texture + " " + r.variant).find(filter) == std::string::npos) continue;
        r.ns = time_row(r, inputs, seconds);
        std::printf("%-12s %-40s %4d %12.1f\n", r.texture.c_str(), r.variant.c_str(), r.dims, r.ns);
        std::fflush(stdout);
        done.push_back(&r);
    }
    std::ofstream csv(csv_path);
    if (!csv) {
        std::fprintf(stderr, "cannot write %s\n", csv_path.c_str());
        return 1;
    }
    csv << "texture,variant,dims,ns_per_call\n";
    char buf[64];
    for (const Row* r : done) {
        std::snprintf(buf, sizeof buf, "%.1f", r->ns);
        csv << r->texture << ',' << r->variant << ',' << r->dims << ',' << buf << '\n';
    }
    std::printf("wrote %s\n", csv_path.c_str());
    return 0;
}
