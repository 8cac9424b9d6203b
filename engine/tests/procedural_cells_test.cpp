// Voronoi and Brick textures against Cycles 3.4: tables of (input -> Cycles 3.4.1 output) measured by
// rendering an emission plane per node setup (pixel centres snapped, away from cell boundaries), plus
// analytic cases and invariants.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "shading/procedural_cells.h"

using namespace smis;
using namespace smis::shading;

namespace {

enum class Out { Distance, Color, Position, W, Radius };

struct VoronoiCase {
    int dims;
    VoronoiFeature feature;
    VoronoiMetric metric;
    Out out;
    float scale, smoothness, exponent, randomness;
    Vec3 co;
    float w;
    Vec3 expected;  // the socket as Cycles emitted it (scalars as grey)
};

// dims, feature, metric, socket, scale, smoothness, exponent, randomness, vector, w, Cycles value.
const VoronoiCase kVoronoiCases[] = {
    {2, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-0.0262500048f, 1.51125002f, 0.370000005f}, 1.48500001f, {0.4996169f, 0.4996169f, 0.4996169f}},
    {2, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-1.83875f, 0.261250019f, 0.370000005f}, -1.57749999f, {0.453002f, 0.453002f, 0.453002f}},
    {2, VoronoiFeature::F1, VoronoiMetric::Manhattan, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-1.27625f, 1.44875002f, 0.370000005f}, 0.172500014f, {0.248824f, 0.248824f, 0.248824f}},
    {2, VoronoiFeature::F1, VoronoiMetric::Manhattan, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {0.848749995f, 0.323750019f, 0.370000005f}, 1.17250001f, {0.1478655f, 0.1478655f, 0.1478655f}},
    {2, VoronoiFeature::F1, VoronoiMetric::Chebychev, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-0.213750005f, -1.36374998f, 0.370000005f}, -1.57749999f, {0.4807374f, 0.4807374f, 0.4807374f}},
    {2, VoronoiFeature::F1, VoronoiMetric::Chebychev, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-0.526250005f, 1.07375002f, 0.370000005f}, 0.547500014f, {0.6497161f, 0.6497161f, 0.6497161f}},
    {2, VoronoiFeature::F1, VoronoiMetric::Minkowski, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-1.02625f, -1.05124998f, 0.370000005f}, -2.07749987f, {0.6733487f, 0.6733487f, 0.6733487f}},
    {2, VoronoiFeature::F1, VoronoiMetric::Minkowski, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-0.901250005f, -1.11374998f, 0.370000005f}, -2.01499987f, {0.6674907f, 0.6674907f, 0.6674907f}},
    {2, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Color, 2.5f, 0.6f, 1.5f, 0.5f, {-0.651250005f, -2.23874998f, 0.370000005f}, -2.88999987f, {0.5764541f, 0.7658117f, 0.3107532f}},
    {2, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Color, 2.5f, 0.6f, 1.5f, 0.5f, {-0.526250005f, 1.38625002f, 0.370000005f}, 0.860000014f, {0.3795615f, 0.5739715f, 0.7743497f}},
    {2, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Position, 2.5f, 0.6f, 1.5f, 0.5f, {-0.401250005f, 1.01125002f, 0.370000005f}, 0.610000014f, {-0.2189908f, 0.894945f, 0.0f}},
    {2, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Position, 2.5f, 0.6f, 1.5f, 0.5f, {0.286249995f, -1.73874998f, 0.370000005f}, -1.45249999f, {0.1312609f, -1.806709f, 0.0f}},
    {2, VoronoiFeature::F2, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {0.598749995f, -1.80124998f, 0.370000005f}, -1.20249999f, {0.7623564f, 0.7623564f, 0.7623564f}},
    {2, VoronoiFeature::F2, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {1.91125f, -0.426249981f, 0.370000005f}, 1.48500001f, {0.9895974f, 0.9895974f, 0.9895974f}},
    {2, VoronoiFeature::F2, VoronoiMetric::Euclidean, Out::Color, 2.5f, 0.6f, 1.5f, 1.0f, {-1.46375f, -0.863749981f, 0.370000005f}, -2.32749987f, {0.4121761f, 0.942799f, 0.6410542f}},
    {2, VoronoiFeature::F2, VoronoiMetric::Euclidean, Out::Color, 2.5f, 0.6f, 1.5f, 1.0f, {1.03625f, -1.05124998f, 0.370000005f}, -0.0149999857f, {0.8252698f, 0.6988888f, 0.130124f}},
    {2, VoronoiFeature::F2, VoronoiMetric::Euclidean, Out::Position, 2.5f, 0.6f, 1.5f, 1.0f, {1.53625f, 0.573750019f, 0.370000005f}, 2.11000013f, {1.461781f, 0.3802547f, 0.0f}},
    {2, VoronoiFeature::F2, VoronoiMetric::Euclidean, Out::Position, 2.5f, 0.6f, 1.5f, 1.0f, {0.286249995f, -1.23874998f, 0.370000005f}, -0.952499986f, {0.4004831f, -1.53649f, 0.0f}},
    {2, VoronoiFeature::F2, VoronoiMetric::Chebychev, Out::Distance, 2.5f, 0.6f, 1.5f, 0.5f, {0.0362499952f, -0.488749981f, 0.370000005f}, -0.452499986f, {0.4224594f, 0.4224594f, 0.4224594f}},
    {2, VoronoiFeature::F2, VoronoiMetric::Chebychev, Out::Distance, 2.5f, 0.6f, 1.5f, 0.5f, {0.536249995f, -0.363749981f, 0.370000005f}, 0.172500014f, {0.7477475f, 0.7477475f, 0.7477475f}},
    {2, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-0.776250005f, 0.0737500042f, 0.370000005f}, -0.702499986f, {0.3208872f, 0.3208872f, 0.3208872f}},
    {2, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-0.151250005f, -0.0512499958f, 0.370000005f}, -0.202500001f, {0.2558746f, 0.2558746f, 0.2558746f}},
    {2, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Color, 2.5f, 0.6f, 1.5f, 1.0f, {0.973749995f, 1.69875002f, 0.370000005f}, 2.67250013f, {0.2417155f, 0.3223369f, 0.707102f}},
    {2, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Color, 2.5f, 0.6f, 1.5f, 1.0f, {-0.401250005f, 0.948750019f, 0.370000005f}, 0.547500014f, {0.2949343f, 0.8662115f, 0.9784789f}},
    {2, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Position, 2.5f, 0.6f, 1.5f, 1.0f, {0.411249995f, 0.198750004f, 0.370000005f}, 0.610000014f, {0.3441251f, 0.2498139f, 0.0f}},
    {2, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Position, 2.5f, 0.6f, 1.5f, 1.0f, {-0.588750005f, 0.511250019f, 0.370000005f}, -0.0774999857f, {-0.6771563f, 0.4193964f, 0.0f}},
    {2, VoronoiFeature::SmoothF1, VoronoiMetric::Manhattan, Out::Distance, 2.5f, 0.6f, 1.5f, 0.5f, {-0.151250005f, -0.488749981f, 0.370000005f}, -0.639999986f, {0.8071976f, 0.8071976f, 0.8071976f}},
    {2, VoronoiFeature::SmoothF1, VoronoiMetric::Manhattan, Out::Distance, 2.5f, 0.6f, 1.5f, 0.5f, {-1.33875f, 1.69875002f, 0.370000005f}, 0.360000014f, {0.4349947f, 0.4349947f, 0.4349947f}},
    {2, VoronoiFeature::DistanceToEdge, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 1.0f, 1.5f, 1.0f, {-1.58875f, 1.13625002f, 0.370000005f}, -0.452499986f, {0.1233501f, 0.1233501f, 0.1233501f}},
    {2, VoronoiFeature::DistanceToEdge, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 1.0f, 1.5f, 1.0f, {-0.838750005f, -1.61374998f, 0.370000005f}, -2.45249987f, {0.07630729f, 0.07630729f, 0.07630729f}},
    {2, VoronoiFeature::NSphereRadius, VoronoiMetric::Euclidean, Out::Radius, 2.5f, 1.0f, 1.5f, 0.5f, {-0.963750005f, -1.80124998f, 0.370000005f}, -2.76499987f, {0.3546037f, 0.3546037f, 0.3546037f}},
    {2, VoronoiFeature::NSphereRadius, VoronoiMetric::Euclidean, Out::Radius, 2.5f, 1.0f, 1.5f, 0.5f, {-1.15125f, 0.198750004f, 0.370000005f}, -0.952499986f, {0.3796445f, 0.3796445f, 0.3796445f}},
    {2, VoronoiFeature::F1, VoronoiMetric::Minkowski, Out::Distance, 2.5f, 1.0f, 0.7f, 1.0f, {-1.52625f, -2.17624998f, 0.370000005f}, -3.70249987f, {0.7288289f, 0.7288289f, 0.7288289f}},
    {2, VoronoiFeature::F1, VoronoiMetric::Minkowski, Out::Distance, 2.5f, 1.0f, 0.7f, 1.0f, {-1.83875f, -0.113749996f, 0.370000005f}, -1.95249999f, {0.3356492f, 0.3356492f, 0.3356492f}},
    {3, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-1.46375f, 1.63625002f, 0.370000005f}, 0.172500014f, {0.428612f, 0.428612f, 0.428612f}},
    {3, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {1.91125f, -0.238749996f, 0.370000005f}, 1.67250001f, {0.8829779f, 0.8829779f, 0.8829779f}},
    {3, VoronoiFeature::F1, VoronoiMetric::Manhattan, Out::Distance, 2.5f, 0.6f, 1.5f, 0.5f, {0.848749995f, 1.19875002f, 0.370000005f}, 2.04750013f, {0.673963f, 0.673963f, 0.673963f}},
    {3, VoronoiFeature::F1, VoronoiMetric::Manhattan, Out::Distance, 2.5f, 0.6f, 1.5f, 0.5f, {1.16125f, 1.44875002f, 0.370000005f}, 2.61000013f, {0.828556f, 0.828556f, 0.828556f}},
    {3, VoronoiFeature::F1, VoronoiMetric::Chebychev, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-0.838750005f, 0.261250019f, 0.370000005f}, -0.577499986f, {0.3339411f, 0.3339411f, 0.3339411f}},
    {3, VoronoiFeature::F1, VoronoiMetric::Chebychev, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-0.901250005f, -0.488749981f, 0.370000005f}, -1.38999999f, {0.7389977f, 0.7389977f, 0.7389977f}},
    {3, VoronoiFeature::F1, VoronoiMetric::Minkowski, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {1.34875f, -0.301249981f, 0.370000005f}, 1.04750001f, {0.7385141f, 0.7385141f, 0.7385141f}},
    {3, VoronoiFeature::F1, VoronoiMetric::Minkowski, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-1.71375f, -1.17624998f, 0.370000005f}, -2.88999987f, {0.7185484f, 0.7185484f, 0.7185484f}},
    {3, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Color, 2.5f, 0.6f, 1.5f, 1.0f, {0.161249995f, 1.69875002f, 0.370000005f}, 1.86000001f, {0.9780388f, 0.06364897f, 0.1355188f}},
    {3, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Color, 2.5f, 0.6f, 1.5f, 1.0f, {0.848749995f, -1.30124998f, 0.370000005f}, -0.452499986f, {0.02244095f, 0.4448879f, 0.9973355f}},
    {3, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Position, 2.5f, 0.6f, 1.5f, 1.0f, {-1.46375f, -1.86374998f, 0.370000005f}, -3.32749987f, {-1.580657f, -1.864743f, 0.4534228f}},
    {3, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Position, 2.5f, 0.6f, 1.5f, 1.0f, {-1.08875f, -1.48874998f, 0.370000005f}, -2.57749987f, {-1.071407f, -1.568912f, 0.3187571f}},
    {3, VoronoiFeature::F2, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 0.5f, {-0.0887500048f, 1.26125002f, 0.370000005f}, 1.17250001f, {0.7820543f, 0.7820543f, 0.7820543f}},
    {3, VoronoiFeature::F2, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 0.5f, {-0.776250005f, 0.511250019f, 0.370000005f}, -0.264999986f, {0.9160265f, 0.9160265f, 0.9160265f}},
    {3, VoronoiFeature::F2, VoronoiMetric::Minkowski, Out::Color, 2.5f, 0.6f, 1.5f, 1.0f, {1.22375f, -0.801249981f, 0.370000005f}, 0.422500014f, {0.1335492f, 0.2199315f, 0.404045f}},
    {3, VoronoiFeature::F2, VoronoiMetric::Minkowski, Out::Color, 2.5f, 0.6f, 1.5f, 1.0f, {2.03625011f, 0.573750019f, 0.370000005f}, 2.61000013f, {0.2099184f, 0.7721938f, 0.6299368f}},
    {3, VoronoiFeature::F2, VoronoiMetric::Manhattan, Out::Position, 2.5f, 0.6f, 1.5f, 1.0f, {-0.963750005f, -2.23874998f, 0.370000005f}, -3.20249987f, {-1.010814f, -2.385964f, 0.09045038f}},
    {3, VoronoiFeature::F2, VoronoiMetric::Manhattan, Out::Position, 2.5f, 0.6f, 1.5f, 1.0f, {0.661249995f, 0.198750004f, 0.370000005f}, 0.860000014f, {0.6646689f, 0.4205848f, 0.34605f}},
    {3, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-0.0262500048f, 0.386250019f, 0.370000005f}, 0.360000014f, {0.4139299f, 0.4139299f, 0.4139299f}},
    {3, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {1.66125f, -1.67624998f, 0.370000005f}, -0.0149999857f, {0.7227345f, 0.7227345f, 0.7227345f}},
    {3, VoronoiFeature::SmoothF1, VoronoiMetric::Chebychev, Out::Color, 2.5f, 0.6f, 1.5f, 0.5f, {-1.83875f, -1.11374998f, 0.370000005f}, -2.95249987f, {0.7249877f, 0.681132f, 0.1654719f}},
    {3, VoronoiFeature::SmoothF1, VoronoiMetric::Chebychev, Out::Color, 2.5f, 0.6f, 1.5f, 0.5f, {-1.40125f, 1.63625002f, 0.370000005f}, 0.235000014f, {0.5866144f, 0.5534452f, 0.7270731f}},
    {3, VoronoiFeature::SmoothF1, VoronoiMetric::Minkowski, Out::Position, 2.5f, 0.6f, 1.5f, 1.0f, {1.78625f, -1.55124998f, 0.370000005f}, 0.235000014f, {1.688744f, -1.397095f, 0.353534f}},
    {3, VoronoiFeature::SmoothF1, VoronoiMetric::Minkowski, Out::Position, 2.5f, 0.6f, 1.5f, 1.0f, {0.348749995f, -0.238749996f, 0.370000005f}, 0.109999999f, {0.3170413f, -0.07601063f, 0.2406349f}},
    {3, VoronoiFeature::DistanceToEdge, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 1.0f, 1.5f, 0.5f, {-1.02625f, 1.13625002f, 0.370000005f}, 0.110000014f, {0.03132457f, 0.03132457f, 0.03132457f}},
    {3, VoronoiFeature::DistanceToEdge, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 1.0f, 1.5f, 0.5f, {-0.651250005f, 0.573750019f, 0.370000005f}, -0.0774999857f, {0.1742712f, 0.1742712f, 0.1742712f}},
    {3, VoronoiFeature::NSphereRadius, VoronoiMetric::Euclidean, Out::Radius, 2.5f, 1.0f, 1.5f, 1.0f, {1.09875f, 0.698750019f, 0.370000005f}, 1.79750001f, {0.2863728f, 0.2863728f, 0.2863728f}},
    {3, VoronoiFeature::NSphereRadius, VoronoiMetric::Euclidean, Out::Radius, 2.5f, 1.0f, 1.5f, 1.0f, {0.411249995f, -2.11374998f, 0.370000005f}, -1.70249999f, {0.2385863f, 0.2385863f, 0.2385863f}},
    {3, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Distance, 7.3f, 1.0f, 1.5f, 1.0f, {0.348749995f, -1.86374998f, 0.370000005f}, -1.51499999f, {0.6070869f, 0.6070869f, 0.6070869f}},
    {3, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Distance, 7.3f, 1.0f, 1.5f, 1.0f, {2.03625011f, -1.17624998f, 0.370000005f}, 0.860000134f, {0.6955412f, 0.6955412f, 0.6955412f}},
    {1, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {0.348749995f, 0.636250019f, 0.370000005f}, 0.985000014f, {0.4223869f, 0.4223869f, 0.4223869f}},
    {1, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {1.09875f, -0.301249981f, 0.370000005f}, 0.797500014f, {0.8453898f, 0.8453898f, 0.8453898f}},
    {1, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Color, 2.5f, 0.6f, 1.5f, 1.0f, {1.34875f, 0.448750019f, 0.370000005f}, 1.79750001f, {0.00449501f, 0.771546f, 0.3814002f}},
    {1, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Color, 2.5f, 0.6f, 1.5f, 1.0f, {0.661249995f, 1.19875002f, 0.370000005f}, 1.86000001f, {0.00449501f, 0.771546f, 0.3814002f}},
    {1, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::W, 2.5f, 0.6f, 1.5f, 1.0f, {-1.15125f, 0.136250004f, 0.370000005f}, -1.01499999f, {-1.1868f, -1.1868f, -1.1868f}},
    {1, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::W, 2.5f, 0.6f, 1.5f, 1.0f, {-1.58875f, 0.323750019f, 0.370000005f}, -1.26499999f, {-1.1868f, -1.1868f, -1.1868f}},
    {1, VoronoiFeature::F2, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 0.5f, {0.473749995f, 0.386250019f, 0.370000005f}, 0.860000014f, {1.07582f, 1.07582f, 1.07582f}},
    {1, VoronoiFeature::F2, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 0.5f, {-1.15125f, -1.92624998f, 0.370000005f}, -3.07749987f, {1.021015f, 1.021015f, 1.021015f}},
    {1, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-0.151250005f, -0.926249981f, 0.370000005f}, -1.07749999f, {0.2732501f, 0.2732501f, 0.2732501f}},
    {1, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-1.40125f, 0.136250004f, 0.370000005f}, -1.26499999f, {0.1954999f, 0.1954999f, 0.1954999f}},
    {1, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Color, 2.5f, 0.6f, 1.5f, 0.5f, {0.0987499952f, -1.67624998f, 0.370000005f}, -1.57749999f, {0.2930483f, 0.6110598f, 0.6541284f}},
    {1, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Color, 2.5f, 0.6f, 1.5f, 0.5f, {-0.901250005f, -0.738749981f, 0.370000005f}, -1.63999999f, {0.2930483f, 0.6110598f, 0.6541284f}},
    {1, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::W, 2.5f, 0.6f, 1.5f, 1.0f, {-0.526250005f, -0.613749981f, 0.370000005f}, -1.13999999f, {-1.1868f, -1.1868f, -1.1868f}},
    {1, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::W, 2.5f, 0.6f, 1.5f, 1.0f, {1.78625f, -0.738749981f, 0.370000005f}, 1.04750001f, {1.153955f, 1.153955f, 1.153955f}},
    {1, VoronoiFeature::DistanceToEdge, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 1.0f, 1.5f, 1.0f, {-1.33875f, 1.63625002f, 0.370000005f}, 0.297500014f, {0.1216431f, 0.1216431f, 0.1216431f}},
    {1, VoronoiFeature::DistanceToEdge, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 1.0f, 1.5f, 1.0f, {1.16125f, -0.676249981f, 0.370000005f}, 0.485000014f, {0.3471069f, 0.3471069f, 0.3471069f}},
    {1, VoronoiFeature::NSphereRadius, VoronoiMetric::Euclidean, Out::Radius, 2.5f, 1.0f, 1.5f, 0.5f, {-1.46375f, 0.136250004f, 0.370000005f}, -1.32749999f, {0.434988f, 0.434988f, 0.434988f}},
    {1, VoronoiFeature::NSphereRadius, VoronoiMetric::Euclidean, Out::Radius, 2.5f, 1.0f, 1.5f, 0.5f, {0.348749995f, -0.551249981f, 0.370000005f}, -0.202499986f, {0.5220358f, 0.5220358f, 0.5220358f}},
    {4, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 1.0f, 1.5f, 1.0f, {-0.963750005f, 0.323750019f, 0.370000005f}, -0.639999986f, {0.8609886f, 0.8609886f, 0.8609886f}},
    {4, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 1.0f, 1.5f, 1.0f, {2.03625011f, -0.113749996f, 0.370000005f}, 1.92250013f, {0.5569526f, 0.5569526f, 0.5569526f}},
    {4, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Color, 2.5f, 1.0f, 1.5f, 0.5f, {-0.526250005f, 1.57375002f, 0.370000005f}, 1.04750001f, {0.7329026f, 0.5592889f, 0.5613505f}},
    {4, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Color, 2.5f, 1.0f, 1.5f, 0.5f, {-1.65125f, -1.61374998f, 0.370000005f}, -3.26499987f, {0.1609831f, 0.1904264f, 0.8824634f}},
    {4, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Position, 2.5f, 1.0f, 1.5f, 1.0f, {-1.27625f, -0.801249981f, 0.370000005f}, -2.07749987f, {-1.310459f, -0.8145032f, 0.2788063f}},
    {4, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::Position, 2.5f, 1.0f, 1.5f, 1.0f, {-0.463750005f, -0.488749981f, 0.370000005f}, -0.952499986f, {-0.2812527f, -0.4858286f, 0.2471265f}},
    {4, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::W, 2.5f, 1.0f, 1.5f, 1.0f, {0.0362499952f, -2.05124998f, 0.370000005f}, -2.01499987f, {-1.892761f, -1.892761f, -1.892761f}},
    {4, VoronoiFeature::F1, VoronoiMetric::Euclidean, Out::W, 2.5f, 1.0f, 1.5f, 1.0f, {2.09875011f, -0.676249981f, 0.370000005f}, 1.42250013f, {1.396081f, 1.396081f, 1.396081f}},
    {4, VoronoiFeature::F2, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-0.901250005f, -1.86374998f, 0.370000005f}, -2.76499987f, {0.6821117f, 0.6821117f, 0.6821117f}},
    {4, VoronoiFeature::F2, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {-1.71375f, -0.613749981f, 0.370000005f}, -2.32749987f, {0.6212005f, 0.6212005f, 0.6212005f}},
    {4, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {0.848749995f, -1.42624998f, 0.370000005f}, -0.577499986f, {0.348689f, 0.348689f, 0.348689f}},
    {4, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 0.6f, 1.5f, 1.0f, {1.91125f, 1.51125002f, 0.370000005f}, 3.42250013f, {0.6135179f, 0.6135179f, 0.6135179f}},
    {4, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Color, 2.5f, 0.6f, 1.5f, 1.0f, {1.72375f, -2.23874998f, 0.370000005f}, -0.514999986f, {0.4197541f, 0.3944528f, 0.1210667f}},
    {4, VoronoiFeature::SmoothF1, VoronoiMetric::Euclidean, Out::Color, 2.5f, 0.6f, 1.5f, 1.0f, {1.97375f, 0.448750019f, 0.370000005f}, 2.42250013f, {0.7899266f, 0.4974413f, 0.4145938f}},
    {4, VoronoiFeature::F1, VoronoiMetric::Manhattan, Out::Distance, 2.5f, 1.0f, 1.5f, 1.0f, {2.09875011f, 1.19875002f, 0.370000005f}, 3.29750013f, {1.501489f, 1.501489f, 1.501489f}},
    {4, VoronoiFeature::F1, VoronoiMetric::Manhattan, Out::Distance, 2.5f, 1.0f, 1.5f, 1.0f, {-1.40125f, -0.238749996f, 0.370000005f}, -1.63999999f, {1.153442f, 1.153442f, 1.153442f}},
    {4, VoronoiFeature::F1, VoronoiMetric::Chebychev, Out::Distance, 2.5f, 1.0f, 1.5f, 1.0f, {-1.33875f, -0.113749996f, 0.370000005f}, -1.45249999f, {0.3816211f, 0.3816211f, 0.3816211f}},
    {4, VoronoiFeature::F1, VoronoiMetric::Chebychev, Out::Distance, 2.5f, 1.0f, 1.5f, 1.0f, {1.09875f, 0.386250019f, 0.370000005f}, 1.48500001f, {0.3134149f, 0.3134149f, 0.3134149f}},
    {4, VoronoiFeature::F1, VoronoiMetric::Minkowski, Out::Distance, 2.5f, 1.0f, 1.5f, 1.0f, {-1.08875f, 1.13625002f, 0.370000005f}, 0.0475000143f, {0.451206f, 0.451206f, 0.451206f}},
    {4, VoronoiFeature::F1, VoronoiMetric::Minkowski, Out::Distance, 2.5f, 1.0f, 1.5f, 1.0f, {-1.02625f, 1.13625002f, 0.370000005f}, 0.110000014f, {0.5312719f, 0.5312719f, 0.5312719f}},
    {4, VoronoiFeature::DistanceToEdge, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 1.0f, 1.5f, 1.0f, {0.223749995f, 1.51125002f, 0.370000005f}, 1.73500001f, {0.1168329f, 0.1168329f, 0.1168329f}},
    {4, VoronoiFeature::DistanceToEdge, VoronoiMetric::Euclidean, Out::Distance, 2.5f, 1.0f, 1.5f, 1.0f, {-0.588750005f, 0.198750004f, 0.370000005f}, -0.389999986f, {0.0543935f, 0.0543935f, 0.0543935f}},
    {4, VoronoiFeature::NSphereRadius, VoronoiMetric::Euclidean, Out::Radius, 2.5f, 1.0f, 1.5f, 1.0f, {0.786249995f, 0.0112500042f, 0.370000005f}, 0.797500014f, {0.3519097f, 0.3519097f, 0.3519097f}},
    {4, VoronoiFeature::NSphereRadius, VoronoiMetric::Euclidean, Out::Radius, 2.5f, 1.0f, 1.5f, 1.0f, {0.0362499952f, 1.57375002f, 0.370000005f}, 1.61000001f, {0.3741941f, 0.3741941f, 0.3741941f}},
};

enum class BOut { Color, Fac };

struct BrickCase {
    BOut out;
    // color1 rgb, color2 rgb, mortar rgb, scale, mortar size, mortar smooth, bias, brick width,
    // row height, offset, offset frequency, squash, squash frequency.
    float p[19];
    Vec3 co;
    Vec3 expected;
};

const BrickCase kBrickCases[] = {
    {BOut::Color, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 1.2f, 0.02f, 0.1f, 0.0f, 0.5f, 0.25f, 0.5f, 2.0f, 1.0f, 2.0f}, {0.348749995f, -1.73874998f, 0.370000005f}, {0.1764708f, 0.2890757f, 0.8126048f}},
    {BOut::Color, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 1.2f, 0.02f, 0.1f, 0.0f, 0.5f, 0.25f, 0.5f, 2.0f, 1.0f, 2.0f}, {-0.901250005f, -0.0512499958f, 0.370000005f}, {0.2068639f, 0.2847337f, 0.77787f}},
    {BOut::Color, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 1.2f, 0.02f, 0.1f, 0.0f, 0.5f, 0.25f, 0.5f, 2.0f, 1.0f, 2.0f}, {-1.83875f, -1.48874998f, 0.370000005f}, {0.1958636f, 0.2863053f, 0.7904416f}},
    {BOut::Color, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 1.7f, 0.05f, 0.6f, -0.3f, 0.6f, 0.3f, 0.3f, 3.0f, 0.6f, 2.0f}, {-0.151250005f, -0.113749996f, 0.370000005f}, {0.5757955f, 0.2320293f, 0.3562337f}},
    {BOut::Color, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 1.7f, 0.05f, 0.6f, -0.3f, 0.6f, 0.3f, 0.3f, 3.0f, 0.6f, 2.0f}, {0.973749995f, -2.17624998f, 0.370000005f}, {0.4866009f, 0.2447714f, 0.4581701f}},
    {BOut::Color, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 1.7f, 0.05f, 0.6f, -0.3f, 0.6f, 0.3f, 0.3f, 3.0f, 0.6f, 2.0f}, {-0.838750005f, -1.17624998f, 0.370000005f}, {0.7999998f, 0.1999999f, 0.09999997f}},
    {BOut::Fac, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 1.7f, 0.05f, 0.6f, -0.3f, 0.6f, 0.3f, 0.3f, 3.0f, 0.6f, 2.0f}, {-0.0262500048f, 1.38625002f, 0.370000005f}, {0.1247606f, 0.1247606f, 0.1247606f}},
    {BOut::Fac, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 1.7f, 0.05f, 0.6f, -0.3f, 0.6f, 0.3f, 0.3f, 3.0f, 0.6f, 2.0f}, {-0.588750005f, 0.511250019f, 0.370000005f}, {0.7010522f, 0.7010522f, 0.7010522f}},
    {BOut::Fac, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 1.7f, 0.05f, 0.6f, -0.3f, 0.6f, 0.3f, 0.3f, 3.0f, 0.6f, 2.0f}, {0.786249995f, 1.57375002f, 0.370000005f}, {0.9360294f, 0.9360294f, 0.9360294f}},
    {BOut::Color, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 0.9f, 0.08f, 0.3f, 0.4f, 0.5f, 0.25f, 0.7f, 1.0f, 1.5f, 3.0f}, {-0.838750005f, 1.69875002f, 0.370000005f}, {0.04999999f, 0.04999999f, 0.04999999f}},
    {BOut::Color, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 0.9f, 0.08f, 0.3f, 0.4f, 0.5f, 0.25f, 0.7f, 1.0f, 1.5f, 3.0f}, {1.47375f, -2.11374998f, 0.370000005f}, {0.2648215f, 0.276454f, 0.7116324f}},
    {BOut::Color, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 0.9f, 0.08f, 0.3f, 0.4f, 0.5f, 0.25f, 0.7f, 1.0f, 1.5f, 3.0f}, {0.411249995f, -0.801249981f, 0.370000005f}, {0.04999999f, 0.04999999f, 0.04999999f}},
    {BOut::Fac, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 0.9f, 0.08f, 0.3f, 0.4f, 0.5f, 0.25f, 0.7f, 1.0f, 1.5f, 3.0f}, {-0.651250005f, -1.17624998f, 0.370000005f}, {0.9667283f, 0.9667283f, 0.9667283f}},
    {BOut::Fac, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 0.9f, 0.08f, 0.3f, 0.4f, 0.5f, 0.25f, 0.7f, 1.0f, 1.5f, 3.0f}, {-1.65125f, 0.636250019f, 0.370000005f}, {0.2252513f, 0.2252513f, 0.2252513f}},
    {BOut::Fac, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 0.9f, 0.08f, 0.3f, 0.4f, 0.5f, 0.25f, 0.7f, 1.0f, 1.5f, 3.0f}, {-0.776250005f, -1.86374998f, 0.370000005f}, {0.2252483f, 0.2252483f, 0.2252483f}},
    {BOut::Color, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 1.3f, 0.04f, 0.0f, 0.1f, 0.5f, 0.25f, 0.25f, 2.0f, 0.5f, 1.0f}, {-0.401250005f, 0.698750019f, 0.370000005f}, {0.04999999f, 0.04999999f, 0.04999999f}},
    {BOut::Color, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 1.3f, 0.04f, 0.0f, 0.1f, 0.5f, 0.25f, 0.25f, 2.0f, 0.5f, 1.0f}, {-1.65125f, 0.0737500042f, 0.370000005f}, {0.5112813f, 0.2412454f, 0.429964f}},
    {BOut::Color, {0.8f, 0.2f, 0.1f, 0.1f, 0.3f, 0.9f, 0.05f, 0.05f, 0.05f, 1.3f, 0.04f, 0.0f, 0.1f, 0.5f, 0.25f, 0.25f, 2.0f, 0.5f, 1.0f}, {1.53625f, -0.301249981f, 0.370000005f}, {0.4136734f, 0.2551894f, 0.5415162f}},
};

Vec3 socket(const VoronoiOut& v, Out o) {
    switch (o) {
        case Out::Distance: return Vec3(v.distance);
        case Out::Color: return v.color;
        case Out::Position: return v.position;
        case Out::W: return Vec3(v.w);
        case Out::Radius: return Vec3(v.radius);
    }
    return Vec3(0.0f);
}

BrickOut eval_brick(const BrickCase& c, const Vec3& co) {
    const float* p = c.p;
    return brick_texture(co, {p[0], p[1], p[2]}, {p[3], p[4], p[5]}, {p[6], p[7], p[8]}, p[9], p[10],
                         p[11], p[12], p[13], p[14], p[15], static_cast<int>(p[16]), p[17],
                         static_cast<int>(p[18]));
}

// Deterministic pseudo-random points for the invariant tests.
float unit(uint32_t& s) {
    s = s * 1664525u + 1013904223u;
    return static_cast<float>(s >> 8) * (1.0f / 16777216.0f);
}

const VoronoiMetric kMetrics[] = {VoronoiMetric::Euclidean, VoronoiMetric::Manhattan,
                                  VoronoiMetric::Chebychev, VoronoiMetric::Minkowski};

}  // namespace

TEST(ProceduralCells, VoronoiMatchesCyclesTable) {
    constexpr float kTol = 2e-3f;
    int index = 0;
    for (const VoronoiCase& c : kVoronoiCases) {
        SCOPED_TRACE(::testing::Message() << "case " << index++ << " dims " << c.dims);
        VoronoiOut v = voronoi_texture(c.dims, c.feature, c.metric, c.co, c.w, c.scale, c.smoothness,
                                       c.exponent, c.randomness);
        Vec3 got = socket(v, c.out);
        EXPECT_NEAR(got.x, c.expected.x, kTol);
        EXPECT_NEAR(got.y, c.expected.y, kTol);
        EXPECT_NEAR(got.z, c.expected.z, kTol);
    }
}

TEST(ProceduralCells, BrickMatchesCyclesTable) {
    constexpr float kTol = 2e-3f;
    int index = 0;
    for (const BrickCase& c : kBrickCases) {
        SCOPED_TRACE(::testing::Message() << "case " << index++);
        BrickOut b = eval_brick(c, c.co);
        Vec3 got = c.out == BOut::Fac ? Vec3(b.fac) : b.color;
        EXPECT_NEAR(got.x, c.expected.x, kTol);
        EXPECT_NEAR(got.y, c.expected.y, kTol);
        EXPECT_NEAR(got.z, c.expected.z, kTol);
    }
}

// Randomness 0 puts every feature point on the integer lattice, so the results are known exactly.
TEST(ProceduralCells, VoronoiLatticeWithoutRandomness) {
    const Vec3 co(0.3f, 0.6f, 0.1f);
    VoronoiOut f1 = voronoi_texture(2, VoronoiFeature::F1, VoronoiMetric::Euclidean, co, 0.0f, 1.0f,
                                    1.0f, 1.0f, 0.0f);
    EXPECT_NEAR(f1.distance, 0.5f, 1e-6f);  // to (0, 1)
    EXPECT_NEAR(f1.position.x, 0.0f, 1e-6f);
    EXPECT_NEAR(f1.position.y, 1.0f, 1e-6f);
    VoronoiOut man = voronoi_texture(3, VoronoiFeature::F1, VoronoiMetric::Manhattan, co, 0.0f, 1.0f,
                                     1.0f, 1.0f, 0.0f);
    EXPECT_NEAR(man.distance, 0.8f, 1e-6f);  // |0.3| + |0.4| + |0.1| to (0, 1, 0)
    VoronoiOut cheb = voronoi_texture(3, VoronoiFeature::F1, VoronoiMetric::Chebychev, co, 0.0f,
                                      1.0f, 1.0f, 1.0f, 0.0f);
    EXPECT_NEAR(cheb.distance, 0.4f, 1e-6f);
    VoronoiOut edge = voronoi_texture(2, VoronoiFeature::DistanceToEdge, VoronoiMetric::Euclidean, co,
                                      0.0f, 1.0f, 1.0f, 1.0f, 0.0f);
    EXPECT_NEAR(edge.distance, 0.1f, 1e-6f);  // edge at y = 0.5
    VoronoiOut radius = voronoi_texture(3, VoronoiFeature::NSphereRadius, VoronoiMetric::Euclidean, co,
                                        0.0f, 1.0f, 1.0f, 1.0f, 0.0f);
    EXPECT_NEAR(radius.radius, 0.5f, 1e-6f);
    VoronoiOut edge1 = voronoi_texture(1, VoronoiFeature::DistanceToEdge, VoronoiMetric::Euclidean, co,
                                       0.3f, 1.0f, 1.0f, 1.0f, 0.0f);
    EXPECT_NEAR(edge1.distance, 0.2f, 1e-6f);  // midpoints at +-0.5
    // Scale 2 doubles the coordinates; Position comes back in input space.
    VoronoiOut scaled = voronoi_texture(2, VoronoiFeature::F1, VoronoiMetric::Euclidean, co * 0.5f,
                                        0.0f, 2.0f, 1.0f, 1.0f, 0.0f);
    EXPECT_NEAR(scaled.distance, 0.5f, 1e-6f);
    EXPECT_NEAR(scaled.position.y, 0.5f, 1e-6f);
    // Scale 0 divides by zero in Cycles' safe_divide: Position is zero.
    VoronoiOut zero = voronoi_texture(3, VoronoiFeature::F1, VoronoiMetric::Euclidean, co, 0.0f, 0.0f,
                                      1.0f, 1.0f, 1.0f);
    EXPECT_EQ(zero.position, Vec3(0.0f));
}

TEST(ProceduralCells, VoronoiInvariants) {
    uint32_t s = 12345u;
    for (int n = 0; n < 200; ++n) {
        Vec3 co(unit(s) * 20.0f - 10.0f, unit(s) * 20.0f - 10.0f, unit(s) * 20.0f - 10.0f);
        float w = unit(s) * 20.0f - 10.0f;
        float rnd = unit(s);
        for (int dims = 1; dims <= 4; ++dims) {
            for (VoronoiMetric m : kMetrics) {
                VoronoiOut f1 = voronoi_texture(dims, VoronoiFeature::F1, m, co, w, 1.3f, 1.0f, 1.5f, rnd);
                VoronoiOut f2 = voronoi_texture(dims, VoronoiFeature::F2, m, co, w, 1.3f, 1.0f, 1.5f, rnd);
                EXPECT_GE(f2.distance, f1.distance);
                EXPECT_GE(f1.distance, 0.0f);
                for (int i = 0; i < 3; ++i) {
                    EXPECT_GE(f1.color[i], 0.0f);
                    EXPECT_LE(f1.color[i], 1.0f);
                }
                if (dims <= 3 && n % 4 == 0) {  // the 4D smooth 5^4 block is slow; sample it less
                    VoronoiOut sf1 = voronoi_texture(dims, VoronoiFeature::SmoothF1, m, co, w, 1.3f,
                                                     0.5f, 1.5f, rnd);
                    EXPECT_LE(sf1.distance, f1.distance + 1e-6f);  // a smooth minimum never exceeds F1
                }
            }
            VoronoiOut r = voronoi_texture(dims, VoronoiFeature::NSphereRadius, VoronoiMetric::Euclidean,
                                           co, w, 1.3f, 1.0f, 1.0f, rnd);
            EXPECT_GE(r.radius, 0.0f);
            EXPECT_LE(r.radius, 1.5f);
            EXPECT_EQ(r.position, Vec3(0.0f));
            EXPECT_EQ(r.color, Vec3(0.0f));
        }
        // 1D reads only W and ignores the metric.
        VoronoiOut a = voronoi_texture(1, VoronoiFeature::F1, VoronoiMetric::Euclidean, co, w, 1.3f, 1.0f,
                                       1.5f, rnd);
        VoronoiOut b = voronoi_texture(1, VoronoiFeature::F1, VoronoiMetric::Chebychev, Vec3(0.0f), w,
                                       1.3f, 1.0f, 1.5f, rnd);
        EXPECT_EQ(a.distance, b.distance);
        EXPECT_EQ(a.color, b.color);
        EXPECT_EQ(a.w, b.w);
        EXPECT_EQ(a.position, Vec3(0.0f));
    }
}

TEST(ProceduralCells, BrickStructure) {
    const Color c1(0.8f, 0.2f, 0.1f), c2(0.1f, 0.3f, 0.9f), mortar(0.05f);
    // Hard mortar: brick corners are mortar, brick centres are a tint between the two colours.
    BrickOut corner = brick_texture(Vec3(0.0f, 0.0f, 0.0f), c1, c2, mortar, 1.0f, 0.02f, 0.0f, 0.0f,
                                    0.5f, 0.25f, 0.5f, 2, 1.0f, 1);
    EXPECT_EQ(corner.fac, 1.0f);
    EXPECT_EQ(corner.color, mortar);
    uint32_t s = 99u;
    for (int n = 0; n < 100; ++n) {
        float row = std::floor(unit(s) * 40.0f - 20.0f), col = std::floor(unit(s) * 40.0f - 20.0f);
        // Row 'row' is offset by half a brick when row is even (frequency 2), so aim at its centre.
        float shift = std::fmod(row, 2.0f) == 0.0f ? 0.25f : 0.0f;
        Vec3 p(col * 0.5f + 0.25f - shift, row * 0.25f + 0.125f, 0.0f);
        BrickOut b = brick_texture(p, c1, c2, mortar, 1.0f, 0.02f, 0.1f, 0.0f, 0.5f, 0.25f, 0.5f, 2,
                                   1.0f, 1);
        EXPECT_EQ(b.fac, 0.0f);
        // Inside a brick the colour is color1 + tint * (color2 - color1) with tint in [0, 1].
        float t = (b.color.x - c1.x) / (c2.x - c1.x);
        EXPECT_GE(t, -1e-5f);
        EXPECT_LE(t, 1.0f + 1e-5f);
        EXPECT_NEAR(b.color.z, c1.z + t * (c2.z - c1.z), 1e-5f);
        // Bias 1 saturates every brick to color2, bias -1 to color1.
        EXPECT_EQ(brick_texture(p, c1, c2, mortar, 1.0f, 0.02f, 0.1f, 1.0f, 0.5f, 0.25f, 0.5f, 2, 1.0f, 1).color, c2);
        EXPECT_EQ(brick_texture(p, c1, c2, mortar, 1.0f, 0.02f, 0.1f, -1.0f, 0.5f, 0.25f, 0.5f, 2, 1.0f, 1).color, c1);
    }
}
