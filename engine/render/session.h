// A render session: progressive passes of an integrator over the film on a pool of worker threads,
// with a time limit, prompt cancellation and progress reporting. Blender polls it from Python while
// the render runs in native threads.
#pragma once
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "integrators/integrator.h"

namespace smis {

struct RenderProgress {
    uint32_t samples_done = 0, samples_total = 0;
    double fraction = 0.0, elapsed = 0.0, paths_per_second = 0.0;
    bool finished = false, cancelled = false;
    uint64_t paths = 0, nan_caught = 0, samples_rejected = 0;
};

class RenderSession {
public:
    RenderSession(std::shared_ptr<const Scene> scene, RenderSettings settings);
    ~RenderSession();
    void start();                     // returns at once; renders on a background thread
    void run();                       // renders on the calling thread (tests, benchmarks)
    bool wait(double timeout_seconds);  // true once finished
    void cancel() { cancel_.store(true); }
    RenderProgress progress() const;
    std::vector<float> pixels() const { return film_.resolve(); }  // window RGBA, bottom row first
    int width() const { return film_.width(); }
    int height() const { return film_.height(); }
    std::map<std::string, double> integrator_stats() const { return integrator_->stats(); }
    // Everything the scene analysis and the integrator switched off for this render.
    std::vector<std::string> skipped() const;
    // An auxiliary pass, averaged (empty unless settings.aux_passes).
    std::vector<float> aux_pixels(AuxPass pass) const { return film_.resolve_aux(pass); }
    // The error that ended the render, if one did (re-thrown by wait()/run() callers).
    std::string error() const;

private:
    void render_loop();
    bool started() const { return start_time_.time_since_epoch().count() != 0; }
    std::shared_ptr<const Scene> scene_;
    RenderSettings settings_;
    Film film_;
    PixelFilter filter_;
    RenderCounters counters_;
    std::unique_ptr<Integrator> integrator_;
    std::atomic<bool> cancel_{false}, finished_{false};
    std::atomic<uint32_t> samples_done_{0};
    std::chrono::steady_clock::time_point start_time_, end_time_;
    std::thread worker_;
    mutable std::mutex mutex_;
    std::condition_variable done_cv_;
    std::string error_;
};

}  // namespace smis
