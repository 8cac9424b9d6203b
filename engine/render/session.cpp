#include "render/session.h"

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

namespace smis {

RenderSession::RenderSession(std::shared_ptr<const Scene> scene, RenderSettings settings)
    : scene_(std::move(scene)),
      settings_(std::move(settings)),
      film_(scene_->camera().window_width(), scene_->camera().window_height()),
      filter_(settings_.filter, settings_.filter_width),
      integrator_(make_integrator(settings_, *scene_)) {
    if (settings_.samples == 0) settings_.samples = 1;
    if (settings_.max_bounces < 0) settings_.max_bounces = 0;
    if (settings_.aux_passes) {
        require_feature(kWithAuxPasses, "render passes", "aux_passes");
        film_.enable_aux(!settings_.aux_shading);  // Z alone: one channel
    }
    if (settings_.film_transparent || scene_->has_holdout()) film_.enable_transparency();
}

std::vector<std::string> RenderSession::skipped() const {
    std::vector<std::string> out = scene_->skipped();
    // Spectral rendering is a mode of every integrator; AUTO resolves to RGB without spectral content
    // (and with photon planes, RGB estimators).
    if (resolve_spectral_mode(settings_, *scene_) == SpectralSetting::Rgb)
        out.push_back(scene_->has_spectral_content() && settings_.volume_estimator != VolumeEstimator::Path
                          ? "spectral (not with photon planes: RGB)"
                          : "spectral");
    if (!scene_->has_media()) out.push_back("volumes");
    if (!settings_.aux_passes) out.push_back("passes");
    if (settings_.sampling_pattern != SamplingPattern::Stratified) out.push_back("stratified sampling");
    integrator_->add_skipped(settings_, &out);
    return out;
}

RenderSession::~RenderSession() {
    cancel();
    if (worker_.joinable()) worker_.join();
}

void RenderSession::start() {
    if (worker_.joinable()) return;
    start_time_ = std::chrono::steady_clock::now();  // before the thread: progress() reads it
    worker_ = std::thread([this] { render_loop(); });
}

void RenderSession::run() {
    start_time_ = std::chrono::steady_clock::now();
    render_loop();
    if (!error_.empty()) throw std::runtime_error(error_);
}

bool RenderSession::wait(double timeout_seconds) {
    std::unique_lock<std::mutex> lock(mutex_);
    auto done = [this] { return finished_.load(); };
    if (timeout_seconds < 0) done_cv_.wait(lock, done);
    else done_cv_.wait_for(lock, std::chrono::duration<double>(timeout_seconds), done);
    return finished_.load();
}

std::string RenderSession::error() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return error_;
}

void RenderSession::render_loop() {
    auto deadline = settings_.time_limit > 0
                        ? start_time_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                            std::chrono::duration<double>(settings_.time_limit))
                        : std::chrono::steady_clock::time_point::max();
    RenderContext ctx{*scene_, settings_, film_, filter_, counters_, cancel_, deadline};
    // The first pass ignores the time limit (only cancelling stops it): a limit shorter than one
    // sample (or one iteration of a multi-stage integrator) gives that sample, not an empty image.
    RenderContext first_pass{*scene_, settings_, film_, filter_, counters_, cancel_,
                             std::chrono::steady_clock::time_point::max()};
    int threads = settings_.threads > 0 ? settings_.threads : tbb::info::default_concurrency();
    try {
        tbb::task_arena arena(threads);
        // Passes grow from 1 sample so the first preview comes quickly, then double up to the
        // integrator's pass size so progress and cancellation stay responsive. Pass boundaries do
        // not change the image.
        uint32_t s = 0, step = 1;
        while (s < settings_.samples && (s == 0 || !ctx.should_stop())) {
            uint32_t e = std::min(settings_.samples, s + step);
            RenderContext& pass = s == 0 ? first_pass : ctx;
            arena.execute([&] { integrator_->render_pass(pass, s, e); });
            if (pass.should_stop()) break;
            s = e;
            samples_done_.store(s);
            step = std::min<uint32_t>(step * 2, integrator_->max_pass_samples());
        }
    } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(mutex_);
        error_ = e.what();
    }
    end_time_ = std::chrono::steady_clock::now();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        finished_.store(true);
    }
    done_cv_.notify_all();
}

RenderProgress RenderSession::progress() const {
    RenderProgress p;
    p.samples_total = settings_.samples;
    p.samples_done = samples_done_.load();
    p.finished = finished_.load();
    p.cancelled = cancel_.load();
    p.paths = counters_.paths.load();
    p.nan_caught = counters_.nan_caught.load();
    p.samples_rejected = counters_.samples_rejected.load();
    auto now = p.finished ? end_time_ : std::chrono::steady_clock::now();
    p.elapsed = started() ? std::chrono::duration<double>(now - start_time_).count() : 0.0;
    double pixels = double(film_.width()) * film_.height();
    p.fraction = std::min(1.0, p.paths / (pixels * settings_.samples));
    p.paths_per_second = p.elapsed > 0 ? p.paths / p.elapsed : 0.0;
    return p;
}

}  // namespace smis
