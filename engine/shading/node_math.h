// Colour and converter node maths of Cycles 3.4 (Math, Vector Math, Mix / MixRGB, Hue/Saturation/
// Value, Bright/Contrast, Gamma, Invert, RGB to BW, Blackbody, Wavelength, Map Range, Clamp, Color Ramp
// and RGB / Vector Curves lookups) as pure functions.
//
// Each function reproduces what Cycles 3.4's CPU kernel computes for the node, including its "safe"
// edge cases (division by zero gives 0, log of a non-positive number gives 0, ...), with the same
// order of float operations where that changes the last bits. Options that Cycles applies as a
// separate step (the Math / Vector Math / Mix "Clamp" result option, the MixRGB factor clamp) are left
// to the caller, as noted per function. Verified against Blender 3.4.1 renders (see node_math_test.cpp).
#pragma once
#include <cstdint>
#include "core/math.h"

namespace smis::shading {

// ---------------------------------------------------------------------------------------------------
// Math node. Enumerators follow the order of Blender's RNA item list (rna_enum_node_math_items), so an
// add-on can map `node.operation` by identifier; the comment gives each identifier.
enum class MathOp : uint8_t {
    Add,          // 'ADD'
    Subtract,     // 'SUBTRACT'
    Multiply,     // 'MULTIPLY'
    Divide,       // 'DIVIDE'
    MultiplyAdd,  // 'MULTIPLY_ADD'
    Power,        // 'POWER'
    Logarithm,    // 'LOGARITHM'
    Sqrt,         // 'SQRT'
    InverseSqrt,  // 'INVERSE_SQRT'
    Absolute,     // 'ABSOLUTE'
    Exponent,     // 'EXPONENT'
    Minimum,      // 'MINIMUM'
    Maximum,      // 'MAXIMUM'
    LessThan,     // 'LESS_THAN'
    GreaterThan,  // 'GREATER_THAN'
    Sign,         // 'SIGN'
    Compare,      // 'COMPARE'
    SmoothMin,    // 'SMOOTH_MIN'
    SmoothMax,    // 'SMOOTH_MAX'
    Round,        // 'ROUND'
    Floor,        // 'FLOOR'
    Ceil,         // 'CEIL'
    Trunc,        // 'TRUNC'
    Fract,        // 'FRACT'
    Modulo,       // 'MODULO'
    Wrap,         // 'WRAP'
    Snap,         // 'SNAP'
    PingPong,     // 'PINGPONG'
    Sine,         // 'SINE'
    Cosine,       // 'COSINE'
    Tangent,      // 'TANGENT'
    Arcsine,      // 'ARCSINE'
    Arccosine,    // 'ARCCOSINE'
    Arctangent,   // 'ARCTANGENT'
    Arctan2,      // 'ARCTAN2'
    Sinh,         // 'SINH'
    Cosh,         // 'COSH'
    Tanh,         // 'TANH'
    Radians,      // 'RADIANS'
    Degrees,      // 'DEGREES'
    Count
};
// Inputs a, b, c are the node's three Value sockets (c is used by MULTIPLY_ADD, COMPARE (epsilon),
// SMOOTH_MIN/MAX (distance) and WRAP (min); WRAP's max is b). The node's Clamp option (clamp the
// result to [0, 1]) is applied by the caller.
float math_op(MathOp op, float a, float b, float c);

// ---------------------------------------------------------------------------------------------------
// Vector Math node, RNA order (rna_enum_node_vec_math_items).
enum class VectorMathOp : uint8_t {
    Add,           // 'ADD'
    Subtract,      // 'SUBTRACT'
    Multiply,      // 'MULTIPLY'
    Divide,        // 'DIVIDE'
    MultiplyAdd,   // 'MULTIPLY_ADD'
    CrossProduct,  // 'CROSS_PRODUCT'
    Project,       // 'PROJECT'
    Reflect,       // 'REFLECT'
    Refract,       // 'REFRACT'
    Faceforward,   // 'FACEFORWARD'
    DotProduct,    // 'DOT_PRODUCT'
    Distance,      // 'DISTANCE'
    Length,        // 'LENGTH'
    Scale,         // 'SCALE'
    Normalize,     // 'NORMALIZE'
    Absolute,      // 'ABSOLUTE'
    Minimum,       // 'MINIMUM'
    Maximum,       // 'MAXIMUM'
    Floor,         // 'FLOOR'
    Ceil,          // 'CEIL'
    Fraction,      // 'FRACTION'
    Modulo,        // 'MODULO'
    Wrap,          // 'WRAP'
    Snap,          // 'SNAP'
    Sine,          // 'SINE'
    Cosine,        // 'COSINE'
    Tangent,       // 'TANGENT'
    Count
};
// a, b, c are the three Vector sockets (c: MULTIPLY_ADD addend, FACEFORWARD reference, WRAP min);
// `scale` is the float socket: the factor of SCALE and the IOR ratio (eta) of REFRACT. Ops with a value
// result (DOT_PRODUCT, DISTANCE, LENGTH) write *value_out and set *vector_out to zero; the others write
// *vector_out and set *value_out to 0 (Cycles leaves the unused output undefined; Blender hides it).
// Either pointer may be null.
void vector_math_op(VectorMathOp op, const Vec3& a, const Vec3& b, const Vec3& c, float scale,
                    Vec3* vector_out, float* value_out);
// True when the op's meaningful output is the Value socket rather than the Vector socket.
bool vector_math_outputs_value(VectorMathOp op);

// ---------------------------------------------------------------------------------------------------
// Mix node (3.4's ShaderNodeMix in Color mode, and the legacy ShaderNodeMixRGB). RNA order of
// rna_enum_ramp_blend_items (note COLOR comes before VALUE).
enum class MixBlend : uint8_t {
    Mix,          // 'MIX'
    Darken,       // 'DARKEN'
    Multiply,     // 'MULTIPLY'
    Burn,         // 'BURN'
    Lighten,      // 'LIGHTEN'
    Screen,       // 'SCREEN'
    Dodge,        // 'DODGE'
    Add,          // 'ADD'
    Overlay,      // 'OVERLAY'
    SoftLight,    // 'SOFT_LIGHT'
    LinearLight,  // 'LINEAR_LIGHT'
    Difference,   // 'DIFFERENCE'
    Subtract,     // 'SUBTRACT'
    Divide,       // 'DIVIDE'
    Hue,          // 'HUE'
    Saturation,   // 'SATURATION'
    Color,        // 'COLOR'
    Value,        // 'VALUE'
    Count
};
// `fac` is used as given: the new Mix node clamps it to [0, 1] only when its "Clamp Factor" option is
// on; the legacy MixRGB node ALWAYS clamps it (Cycles' svm_mix_clamped_factor). The "Clamp" (result)
// option of either node is a saturate of the result, applied by the caller.
Color mix_blend(MixBlend blend, float fac, const Color& a, const Color& b);
// Mix node in Float mode: a * (1 - fac) + b * fac (fac clamped by the caller if "Clamp Factor").
float mix_float(float fac, float a, float b);
// Mix node in Vector mode; a uniform factor is Vec3(fac). Same formula per component.
Vec3 mix_vector(const Vec3& fac, const Vec3& a, const Vec3& b);

// Colour models (Cycles' util/color.h; h, s, v / l in [0, 1] for in-gamut colours).
Color rgb_to_hsv(const Color& rgb);
Color hsv_to_rgb(const Color& hsv);
Color rgb_to_hsl(const Color& rgb);
Color hsl_to_rgb(const Color& hsl);

// Hue/Saturation/Value node (hue shift is `hue - 0.5`, the result is clamped at 0 from below).
Color hue_saturation_value(float hue, float saturation, float value, float fac, const Color& color);
// Bright/Contrast node: max((1 + contrast) * c + bright - contrast / 2, 0) per channel.
Color bright_contrast(const Color& color, float bright, float contrast);
// Gamma node: pow per positive channel; gamma 0 gives white.
Color gamma_node(const Color& color, float gamma);
// Invert node: lerp between color and 1 - color.
Color invert_node(float fac, const Color& color);
// RGB to BW node (and Cycles' implicit colour -> float conversion). Cycles weights the channels by the
// Y row of its scene-linear -> XYZ matrix, derived from the OCIO config (srgb_to_xyz.spimtx through
// the ACES interchange role): (0.212672979, 0.715152621, 0.0721754432), not the config's rounded
// `luma` line (0.2126, 0.7152, 0.0722), which Cycles does not read.
float rgb_to_bw(const Color& c);
// Blackbody node: Cycles 3.4's piecewise fit in Rec.709 (no normalisation: 6500 K gives
// (1.0426, 0.9841, 1.0353), 1500 K (3.264, 0.434, 0)), clamped at 0. Below 800 K it holds a fixed dim
// red (5.413, 0, 0), from 12000 K on the 12000 K colour. This is the kernel's value; a Cycles graph
// whose temperature is constant is folded at compile time through a real Rec.709 -> scene-linear
// matrix instead, which differs by up to ~2e-6 absolute.
Color blackbody(float kelvin);
// Wavelength node: CIE 1931 2-degree colour matching table (5 nm steps, 380..780 nm) to Rec.709,
// scaled by 1 / 2.52 and clamped at 0; black outside the open interval (375, 780) nm (Cycles
// truncates the table index towards zero, so 375..380 nm extrapolates the first interval).
Color wavelength_to_rgb(float nm);

// ---------------------------------------------------------------------------------------------------
// Map Range node, RNA order of interpolation_type.
enum class MapRangeType : uint8_t {
    Linear,        // 'LINEAR'
    Stepped,       // 'STEPPED'
    SmoothStep,    // 'SMOOTHSTEP'
    SmootherStep,  // 'SMOOTHERSTEP'
    Count
};
// Float mode. from_min == from_max gives 0 (then clamped, if `clamp`, into the To range). `clamp`
// clamps the result into [to_min, to_max] (either order), as Cycles' Clamp-RANGE node after it.
float map_range(MapRangeType type, float value, float from_min, float from_max, float to_min,
                float to_max, float steps, bool clamp);
// Vector mode: per component, with safe division (from_min == from_max gives factor 0, i.e. to_min);
// `clamp` is ignored for the two smooth types, as in Cycles.
Vec3 map_range_vector(MapRangeType type, const Vec3& value, const Vec3& from_min, const Vec3& from_max,
                      const Vec3& to_min, const Vec3& to_max, const Vec3& steps, bool clamp);

// Clamp node: MINMAX (range = false) is min(max(value, min), max), so min > max gives max; RANGE
// swaps min and max when min > max.
float clamp_node(bool range, float value, float min, float max);

// ---------------------------------------------------------------------------------------------------
// Lookup tables baked by the add-on (Cycles uses 256 entries, RAMP_TABLE_SIZE).
struct Rgba {
    Color rgb;
    float a = 1.0f;
};
// Tables may be stored as flat float arrays (r, g, b, a per entry) and viewed as Rgba.
static_assert(sizeof(Rgba) == 4 * sizeof(float), "Rgba must be four packed floats");
// Color Ramp: `table` holds n >= 2 entries, entry i = ramp.evaluate(i / (n - 1)). interpolate is false
// for the ramp's CONSTANT interpolation (the table itself already carries EASE / CARDINAL / ...).
// Cycles' Color Ramp node calls this with extrapolate = false (f clamped to [0, 1]; NaN gives entry 0).
Rgba ramp_lookup(const Rgba* table, int n, float f, bool interpolate, bool extrapolate);
// RGB Curves node. Table entry i covers x = min_x + (float)i / (float)(n - 1) * (max_x - min_x), where
// min_x / max_x are the smallest first-point x and the largest last-point x of the four curves (C, R,
// G, B); the entry is (R(C(x)), G(C(x)), B(C(x))) with C the combined curve, evaluated with
// CurveMapping.evaluate (Cycles' curvemapping_color_to_array with rgb_curve = true).
// `extrapolate` is the mapping's extend == 'EXTRAPOLATED' (Blender's default for new nodes): outside
// the table the end slope continues, else the end value holds. Each channel reads its own column;
// the result is lerp(in, table value, fac).
Color rgb_curves(const Rgba* table, int n, float min_x, float max_x, float fac, const Color& in,
                 bool extrapolate = true);
// Vector Curves node: the same lookup as rgb_curves; only the table differs: entry i is
// (X(x), Y(x), Z(x)), with min_x / max_x taken over the three curves (no combined curve).
Vec3 vector_curves(const Rgba* table, int n, float min_x, float max_x, float fac, const Vec3& in,
                   bool extrapolate = true);

// ---------------------------------------------------------------------------------------------------
// Blender enum identifier <-> enumerator, for the add-on bridge. Lookups return false for an unknown
// identifier and leave *out untouched.
const char* math_op_name(MathOp op);
const char* vector_math_op_name(VectorMathOp op);
const char* mix_blend_name(MixBlend blend);
const char* map_range_type_name(MapRangeType type);
bool math_op_from_name(const char* identifier, MathOp* out);
bool vector_math_op_from_name(const char* identifier, VectorMathOp* out);
bool mix_blend_from_name(const char* identifier, MixBlend* out);
bool map_range_type_from_name(const char* identifier, MapRangeType* out);

}  // namespace smis::shading
