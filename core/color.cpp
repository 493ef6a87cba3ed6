#include "core/color.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/lanes.hpp"

namespace gltf_pbr {

float srgb_to_linear(float encoded) {
  const float c = std::clamp(encoded, 0.0f, 1.0f);  // also maps NaN-free inputs only; callers check NaN
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

const std::array<float, 256>& srgb8_to_linear_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> linear{};
    for (int code = 0; code < 256; ++code)
      linear[static_cast<std::size_t>(code)] = srgb_to_linear(static_cast<float>(code) / 255.0f);
    return linear;
  }();
  return table;
}

float srgb8_to_linear(std::uint8_t code) { return srgb8_to_linear_table()[code]; }

glm::dvec3 linear_srgb_to_lab(glm::dvec3 rgb) {
  // IEC 61966-2-1 linear sRGB -> XYZ, normalised by the D65 white point.
  const double x = (0.4124564 * rgb.r + 0.3575761 * rgb.g + 0.1804375 * rgb.b) / 0.95047;
  const double y = (0.2126729 * rgb.r + 0.7151522 * rgb.g + 0.0721750 * rgb.b) / 1.00000;
  const double z = (0.0193339 * rgb.r + 0.1191920 * rgb.g + 0.9503041 * rgb.b) / 1.08883;
  // CIE 1976 L*a*b*: cube root with the linear segment below (6/29)^3.
  auto f = [](double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0; };
  return {116.0 * f(y) - 16.0, 500.0 * (f(x) - f(y)), 200.0 * (f(y) - f(z))};
}

double delta_e_2000(glm::dvec3 lab1, glm::dvec3 lab2) {
  // Sharma, Wu, Dalal (2005), equations 1-22. The error statistics call this for every distinct
  // texel, so powers are products, hypot (its overflow care is not needed at Lab's magnitudes) is
  // a square root, and the four cosines of T (equation 15) come from one sine and cosine of the
  // mean hue by the angle-sum and multiple-angle identities.
  constexpr double pi = 3.14159265358979323846;
  constexpr double kPow25To7 = 6103515625.0;  // 25^7
  auto degrees = [](double radians) { return radians * 180.0 / pi; };
  auto radians = [](double deg) { return deg * pi / 180.0; };
  auto seventh = [](double x) {
    const double x2 = x * x;
    return x2 * x2 * x2 * x;
  };
  auto length = [](double a, double b) { return std::sqrt(a * a + b * b); };
  const double c1 = length(lab1.y, lab1.z), c2 = length(lab2.y, lab2.z);
  const double c_mean7 = seventh(0.5 * (c1 + c2));
  const double g = 0.5 * (1.0 - std::sqrt(c_mean7 / (c_mean7 + kPow25To7)));
  const double a1 = (1.0 + g) * lab1.y, a2 = (1.0 + g) * lab2.y;
  const double cp1 = length(a1, lab1.z), cp2 = length(a2, lab2.z);
  auto hue = [&](double b, double a) {
    if (a == 0.0 && b == 0.0) return 0.0;
    const double h = degrees(std::atan2(b, a));
    return h < 0.0 ? h + 360.0 : h;
  };
  const double hp1 = hue(lab1.z, a1), hp2 = hue(lab2.z, a2);
  const double dl = lab2.x - lab1.x, dc = cp2 - cp1;
  double dh = 0.0;
  if (cp1 * cp2 != 0.0) {
    dh = hp2 - hp1;
    if (dh > 180.0) dh -= 360.0;
    if (dh < -180.0) dh += 360.0;
  }
  const double dH = 2.0 * std::sqrt(cp1 * cp2) * std::sin(radians(dh / 2.0));
  const double l_mean = 0.5 * (lab1.x + lab2.x), cp_mean = 0.5 * (cp1 + cp2);
  double h_mean = hp1 + hp2;
  if (cp1 * cp2 != 0.0) {
    if (std::abs(hp1 - hp2) <= 180.0)
      h_mean /= 2.0;
    else
      h_mean = (hp1 + hp2 < 360.0) ? (hp1 + hp2 + 360.0) / 2.0 : (hp1 + hp2 - 360.0) / 2.0;
  }
  // T = 1 - 0.17 cos(h - 30°) + 0.24 cos(2h) + 0.32 cos(3h + 6°) - 0.20 cos(4h - 63°).
  const double ch = std::cos(radians(h_mean)), sh1 = std::sin(radians(h_mean));
  const double c2h = 2.0 * ch * ch - 1.0, s2h = 2.0 * sh1 * ch;
  const double c3h = ch * (4.0 * ch * ch - 3.0), s3h = sh1 * (3.0 - 4.0 * sh1 * sh1);
  const double c4h = 2.0 * c2h * c2h - 1.0, s4h = 2.0 * s2h * c2h;
  static const double cos30 = std::cos(radians(30.0)), sin30 = 0.5;
  static const double cos6 = std::cos(radians(6.0)), sin6 = std::sin(radians(6.0));
  static const double cos63 = std::cos(radians(63.0)), sin63 = std::sin(radians(63.0));
  const double t = 1.0 - 0.17 * (ch * cos30 + sh1 * sin30) + 0.24 * c2h + 0.32 * (c3h * cos6 - s3h * sin6) -
                   0.20 * (c4h * cos63 + s4h * sin63);
  const double theta_offset = (h_mean - 275.0) / 25.0;
  const double d_theta = 30.0 * std::exp(-theta_offset * theta_offset);
  const double cp_mean7 = seventh(cp_mean);
  const double rc = 2.0 * std::sqrt(cp_mean7 / (cp_mean7 + kPow25To7));
  const double l50 = (l_mean - 50.0) * (l_mean - 50.0);
  const double sl = 1.0 + 0.015 * l50 / std::sqrt(20.0 + l50);
  const double sc = 1.0 + 0.045 * cp_mean;
  const double sh = 1.0 + 0.015 * cp_mean * t;
  const double rt = -std::sin(radians(2.0 * d_theta)) * rc;
  const double tl = dl / sl, tc = dc / sc, th = dH / sh;
  return std::sqrt(tl * tl + tc * tc + th * th + rt * tc * th);
}

}  // namespace gltf_pbr

namespace gltf_pbr {
namespace {

using namespace lanes;

// x + 1.5·2^23 rounds x to an integer (to nearest, for |x| < 2^22), which then sits in the low
// bits of the float's mantissa: integers without a float-to-int conversion.
constexpr float kRoundingShift = 12582912.0f;
GLTF_PBR_INLINE Floats shifted(Floats x) { return x + kRoundingShift; }
GLTF_PBR_INLINE Ints integer_of_shifted(Floats shifted_value) {
  return reinterpret_cast<Ints>(shifted_value) - reinterpret_cast<Ints>(splat(kRoundingShift));
}

// Cube root of x >= 216/24389 (Lab's cube-root segment): the exponent divided by three in the
// bits (Kahan's estimate, as in FreeBSD's cbrtf), then Newton's t -= (t³ - x) / 3t², whose
// relative error squares from 3% at each step.
GLTF_PBR_INLINE Floats cube_root(Floats x) {
  const Floats bits = __builtin_convertvector(reinterpret_cast<Ints>(x), Floats);
  Floats t = reinterpret_cast<Floats>(__builtin_convertvector(bits * (1.0f / 3.0f), Ints) + 709958130);
  for (int i = 0; i < 3; ++i) t = t * (2.0f / 3.0f) + x / (3.0f * t * t);
  return t;
}

// sin and cos of |x| < 2^20: x less the nearest multiple n of π/2 (Cody-Waite, three parts of
// π/2), Cephes' sinf/cosf polynomials on [-π/4, π/4], and the quadrant n mod 4.
GLTF_PBR_INLINE void sine_cosine(Floats x, Floats& sine, Floats& cosine) {
  const Floats n_shifted = shifted(x * 0.63661977236758134f);
  const Floats n = n_shifted - kRoundingShift;
  const Floats r = ((x - n * 1.5703125f) - n * 4.837512969970703125e-4f) - n * 7.54978995489188216e-8f;
  const Floats z = r * r;
  const Floats s = ((-1.9515295891e-4f * z + 8.3321608736e-3f) * z - 1.6666654611e-1f) * z * r + r;
  const Floats c =
      ((2.443315711809948e-5f * z - 1.388731625493765e-3f) * z + 4.166664568298827e-2f) * z * z - 0.5f * z + 1.0f;
  const Ints quadrant = integer_of_shifted(n_shifted) & 3;
  const Mask swap = (quadrant & 1) != 0;
  sine = select(swap, c, s);
  cosine = select(swap, s, c);
  sine = select((quadrant & 2) != 0, -sine, sine);
  cosine = select(((quadrant + 1) & 2) != 0, -cosine, cosine);
}

// e^x for x <= 0: 2^n · e^r with r = x - n ln 2 in [-ln2/2, ln2/2] and Cephes' expf polynomial.
// Below -87 (where e^x leaves the normal floats) it is e^-87, near enough to 0 for every use here.
GLTF_PBR_INLINE Floats exp_nonpositive(Floats x) {
  x = select(x < -87.0f, splat(-87.0f), x);  // NaN stays NaN
  const Floats n_shifted = shifted(x * 1.44269504088896341f);
  const Floats n = n_shifted - kRoundingShift;
  const Floats r = (x - n * 0.693359375f) + n * 2.12194440e-4f;
  const Floats p = (((((1.9875691500e-4f * r + 1.3981999507e-3f) * r + 8.3334519073e-3f) * r + 4.1665795894e-2f) * r +
                     1.6666665459e-1f) *
                        r +
                    5.0000001201e-1f) *
                       r * r +
                   r + 1.0f;
  return p * reinterpret_cast<Floats>((integer_of_shifted(n_shifted) + 127) << 23);
}

// atan2(y, x) in degrees on [0, 360), and 0 for (0, 0), as the hue of CIEDE2000 equation 7:
// arctangent of the smaller over the larger magnitude (Cephes' atanf, reduced below tan π/8),
// then placed in its octant.
GLTF_PBR_INLINE Floats hue_degrees(Floats y, Floats x) {
  constexpr float kPi = 3.14159265358979323846f;
  const Floats ax = abs(x), ay = abs(y);
  const Floats larger = max(ax, ay), smaller = min(ax, ay);
  const Floats t = smaller / max(larger, splat(1e-30f));
  const Mask reduced = t > 0.41421356237309505f;
  const Floats u = select(reduced, (t - 1.0f) / (t + 1.0f), t), u2 = u * u;
  Floats angle =
      (((8.05374449538e-2f * u2 - 1.38776856032e-1f) * u2 + 1.99777106478e-1f) * u2 - 3.33329491539e-1f) * u2 * u + u +
      select(reduced, splat(kPi / 4.0f), splat(0.0f));
  angle = select(ay > ax, kPi / 2.0f - angle, angle);
  angle = select(x < 0.0f, kPi - angle, angle);
  angle = select(y < 0.0f, -angle, angle);
  const Floats degrees = angle * (180.0f / kPi);
  return select((x == 0.0f) & (y == 0.0f), splat(0.0f), select(degrees < 0.0f, degrees + 360.0f, degrees));
}

// CIE 1976 L*a*b* of linear sRGB, as linear_srgb_to_lab().
GLTF_PBR_INLINE void lab_of(const Floats (&rgb)[3], Floats (&lab)[3]) {
  const auto f = [](Floats t) {
    constexpr float kEpsilon = 216.0f / 24389.0f;
    return select(t > kEpsilon, cube_root(max(t, splat(kEpsilon))), (24389.0f / 27.0f * t + 16.0f) / 116.0f);
  };
  const Floats fx = f((0.4124564f * rgb[0] + 0.3575761f * rgb[1] + 0.1804375f * rgb[2]) / 0.95047f);
  const Floats fy = f(0.2126729f * rgb[0] + 0.7151522f * rgb[1] + 0.0721750f * rgb[2]);
  const Floats fz = f((0.0193339f * rgb[0] + 0.1191920f * rgb[1] + 0.9503041f * rgb[2]) / 1.08883f);
  lab[0] = 116.0f * fy - 16.0f, lab[1] = 500.0f * (fx - fy), lab[2] = 200.0f * (fy - fz);
}

// delta_e_2000() of every lane: the same equations and identities.
GLTF_PBR_INLINE Floats delta_e_2000_of(const Floats (&lab1)[3], const Floats (&lab2)[3]) {
  constexpr float kPi = 3.14159265358979323846f;
  constexpr float kPow25To7 = 6103515625.0f;
  const auto seventh = [](Floats x) {
    const Floats x2 = x * x;
    return x2 * x2 * x2 * x;
  };
  const auto length = [](Floats a, Floats b) { return square_root(a * a + b * b); };
  const Floats c_mean7 = seventh(0.5f * (length(lab1[1], lab1[2]) + length(lab2[1], lab2[2])));
  const Floats g = 0.5f * (1.0f - square_root(c_mean7 / (c_mean7 + kPow25To7)));
  const Floats a1 = (1.0f + g) * lab1[1], a2 = (1.0f + g) * lab2[1];
  const Floats cp1 = length(a1, lab1[2]), cp2 = length(a2, lab2[2]);
  const Floats hp1 = hue_degrees(lab1[2], a1), hp2 = hue_degrees(lab2[2], a2);
  const Mask chromatic = cp1 * cp2 != 0.0f;
  Floats dh = hp2 - hp1;
  dh = select(dh > 180.0f, dh - 360.0f, dh);
  dh = select(dh < -180.0f, dh + 360.0f, dh);
  dh = select(chromatic, dh, splat(0.0f));
  Floats half_dh_sine, unused;
  sine_cosine(dh * (kPi / 360.0f), half_dh_sine, unused);
  const Floats dH = 2.0f * square_root(cp1 * cp2) * half_dh_sine;
  const Floats l_mean = 0.5f * (lab1[0] + lab2[0]), cp_mean = 0.5f * (cp1 + cp2);
  const Floats sum = hp1 + hp2;
  const Floats h_mean = select(
      chromatic,
      select(abs(hp1 - hp2) <= 180.0f, 0.5f * sum, select(sum < 360.0f, 0.5f * (sum + 360.0f), 0.5f * (sum - 360.0f))),
      sum);
  Floats sh1, ch;
  sine_cosine(h_mean * (kPi / 180.0f), sh1, ch);
  const Floats c2h = 2.0f * ch * ch - 1.0f, s2h = 2.0f * sh1 * ch;
  const Floats c3h = ch * (4.0f * ch * ch - 3.0f), s3h = sh1 * (3.0f - 4.0f * sh1 * sh1);
  const Floats c4h = 2.0f * c2h * c2h - 1.0f, s4h = 2.0f * s2h * c2h;
  constexpr float cos30 = 0.86602540378443865f, sin30 = 0.5f;
  constexpr float cos6 = 0.99452189536827333f, sin6 = 0.10452846326765347f;
  constexpr float cos63 = 0.45399049973954675f, sin63 = 0.89100652418836786f;
  const Floats t = 1.0f - 0.17f * (ch * cos30 + sh1 * sin30) + 0.24f * c2h + 0.32f * (c3h * cos6 - s3h * sin6) -
                   0.20f * (c4h * cos63 + s4h * sin63);
  const Floats theta_offset = (h_mean - 275.0f) / 25.0f;
  const Floats d_theta = 30.0f * exp_nonpositive(-theta_offset * theta_offset);
  const Floats cp_mean7 = seventh(cp_mean);
  const Floats rc = 2.0f * square_root(cp_mean7 / (cp_mean7 + kPow25To7));
  const Floats l50 = (l_mean - 50.0f) * (l_mean - 50.0f);
  const Floats sl = 1.0f + 0.015f * l50 / square_root(20.0f + l50);
  const Floats sc = 1.0f + 0.045f * cp_mean;
  const Floats sh = 1.0f + 0.015f * cp_mean * t;
  Floats rotation_sine;
  sine_cosine(d_theta * (kPi / 90.0f), rotation_sine, unused);
  const Floats rt = -rotation_sine * rc;
  const Floats tl = (lab2[0] - lab1[0]) / sl, tc = (cp2 - cp1) / sc, th = dH / sh;
  // Never below 0 but by rounding; NaN (a colour no float holds) stays NaN, as in the scalar form.
  const Floats squared = tl * tl + tc * tc + th * th + rt * tc * th;
  return square_root(select(squared < 0.0f, splat(0.0f), squared));
}

// The batches, kLanes colours at a time; the last lanes of a short batch repeat its last colour.
template <size_t kArrays>
GLTF_PBR_INLINE void gather(const glm::vec3* colours, size_t count, Floats (&lanes)[kArrays]) {
  float values[kArrays][kLanes];
  for (size_t l = 0; l < kLanes; ++l)
    for (size_t c = 0; c < kArrays; ++c) values[c][l] = colours[std::min(l, count - 1)][static_cast<int>(c)];
  std::memcpy(lanes, values, sizeof values);
}

GLTF_PBR_LANE_CLONES
void lab_batch(const glm::vec3* linear, glm::vec3* lab, size_t count) {
  for (size_t first = 0; first < count; first += kLanes) {
    const size_t n = std::min<size_t>(kLanes, count - first);
    Floats in[3], out[3];
    gather(linear + first, n, in);
    lab_of(in, out);
    for (size_t l = 0; l < n; ++l) lab[first + l] = {out[0][l], out[1][l], out[2][l]};
  }
}

GLTF_PBR_LANE_CLONES
void delta_e_batch(const glm::vec3* lab1, const glm::vec3* lab2, float* delta_e, size_t count) {
  for (size_t first = 0; first < count; first += kLanes) {
    const size_t n = std::min<size_t>(kLanes, count - first);
    Floats a[3], b[3];
    gather(lab1 + first, n, a);
    gather(lab2 + first, n, b);
    const Floats d = delta_e_2000_of(a, b);
    for (size_t l = 0; l < n; ++l) delta_e[first + l] = d[l];
  }
}

}  // namespace

void linear_srgb_to_lab(std::span<const glm::vec3> linear, std::span<glm::vec3> lab) {
  lab_batch(linear.data(), lab.data(), std::min(linear.size(), lab.size()));
}

void delta_e_2000(std::span<const glm::vec3> lab1, std::span<const glm::vec3> lab2, std::span<float> delta_e) {
  delta_e_batch(lab1.data(), lab2.data(), delta_e.data(), std::min({lab1.size(), lab2.size(), delta_e.size()}));
}

}  // namespace gltf_pbr
