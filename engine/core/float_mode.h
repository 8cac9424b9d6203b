// Every render thread computes in the same floating-point mode. The worker threads come from TBB's
// pool, which the host application (Blender) shares and may have configured differently from our
// own thread; if denormal handling differed between threads, a pixel's value would depend on which
// thread rendered it. Set flush-to-zero / denormals-are-zero explicitly (Embree's recommended mode).
#pragma once
#include <xmmintrin.h>
#include <pmmintrin.h>

namespace smis {

class ScopedFlushDenormals {
public:
    ScopedFlushDenormals() : saved_(_mm_getcsr()) {
        _mm_setcsr(saved_ | _MM_FLUSH_ZERO_ON | _MM_DENORMALS_ZERO_ON);
    }
    ~ScopedFlushDenormals() { _mm_setcsr(saved_); }
    ScopedFlushDenormals(const ScopedFlushDenormals&) = delete;
    ScopedFlushDenormals& operator=(const ScopedFlushDenormals&) = delete;

private:
    unsigned int saved_;
};

}  // namespace smis
