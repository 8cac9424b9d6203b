// Fixed-seed image hashes of RGB resampled-light configurations (bit-identity before/after).
#include <cstdio>
#include <cstring>
#include "test_scenes.h"
using namespace smis;
using namespace smis::testing;

static std::shared_ptr<Scene> fog() {
    auto s = std::make_shared<Scene>();
    Medium fog; fog.sigma_a = Color(0.05f, 0.08f, 0.12f); fog.sigma_s = Color(0.7f, 0.6f, 0.45f); fog.phase = HenyeyGreenstein(0.3f);
    Material boundary; boundary.name = "fog"; boundary.pass_through = true; boundary.medium = s->add_medium(fog);
    add_box(*s, {-1.5f, -1.5f, -0.2f}, {1.5f, 1.5f, 2.5f}, s->add_material(boundary));
    add_box(*s, {-1.4f, -1.4f, -0.1f}, {1.4f, 1.4f, 0.0f}, s->add_material(diffuse(Color(0.7f))));
    add_box(*s, {-1.1f, 0.8f, 0.0f}, {0.1f, 0.9f, 1.3f}, s->add_material(glossy(Color(0.9f), 0.0f)));
    add_box(*s, {0.2f, -0.5f, 0.0f}, {0.8f, 0.1f, 0.7f}, s->add_material(smooth_glass(1.5f)));
    add_square_light(*s, 1.0f, 60.0f, {0.0f, 0.0f, 2.2f});
    LightDesc point; point.type = "POINT"; point.power = 15.0f; point.radius = 0.15f;
    point.to_world.m[0][3] = -0.7f, point.to_world.m[1][3] = -0.6f, point.to_world.m[2][3] = 0.9f;
    s->add_light(point);
    s->set_camera(camera_along_y({0.0f, -3.2f, 0.6f}, 24, 24, 30.0f));
    s->commit();
    return s;
}

int main() {
    auto ml = many_lights(24, 24); auto room = small_room(24, 24); auto fg = fog();
    struct Case { const char* scene_name; std::shared_ptr<Scene> s; const char* integ; };
    Case cases[] = {{"many_lights", ml, "PATH+RIS"}, {"small_room", room, "PATH+RIS"}, {"fog", fg, "PATH+RIS"},
                    {"many_lights", ml, "PATH+RESTIR_SEED"}, {"many_lights", ml, "PATH+RESTIR_TALBOT"},
                    {"fog", fg, "PATH+RESTIR_SEED"}, {"fog", fg, "PATH+RESTIR_NONE"}, {"small_room", room, "PATH"},
                    {"fog", fg, "PATH HERO"}, {"fog", fg, "PATH SMIS"}, {"many_lights", ml, "PATH HERO"}, {"small_room", room, "PATH SMIS"}};
    for (auto& c : cases) {
        RenderSettings st; st.max_bounces = 3; st.ris_candidates = 8; st.samples = 4; st.seed = 5;
        std::string name = c.integ;
        if (name.find(' ') != std::string::npos) {
            st.spectral = setting_value<SpectralSetting>(name.substr(name.find(' ') + 1));
            name = name.substr(0, name.find(' '));
        }
        select_integrator(st, name);
        auto img = render(c.s, st);
        uint64_t h = 1469598103934665603ull; double sum = 0;
        for (float v : img) { uint32_t b; std::memcpy(&b, &v, 4); h = (h ^ b) * 1099511628211ull; sum += v; }
        std::printf("%-12s %-20s %016llx mean %.6f\n", c.scene_name, c.integ, (unsigned long long)h, sum / img.size());
    }
}
