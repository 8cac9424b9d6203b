// Instruction counts of spectral NEE (RIS unused) renders, one thread.
#include <cstdio>
#include "test_scenes.h"
using namespace smis;
using namespace smis::testing;
int main() {
    auto room = small_room(24, 24);
    RenderSettings st; st.max_bounces = 4; st.samples = 32; st.seed = 3; st.threads = 1;
    st.spectral = SpectralSetting::Rgb;
    auto img = render(room, st);
    double s = 0; for (float v : img) s += v;
    std::printf("%f\n", s);
}
