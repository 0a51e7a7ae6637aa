#include "render/rain/StreakRaster.h"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "render/frame/Lighting.h"
#include "render/rain/StreakFrame.h"
#include "render/rain/StreakLine.h"
#include "sim/rain/Spotlight.h"

namespace sph::render::rain {
namespace {

using detail::applyRow;
using detail::floorToInt;
using detail::Frame;
using detail::Vec4f;

// GLSL's toSrgb of shaders/rain.vert, component-wise.
Vec3 toSrgb(const Vec3& c) {
  return Vec3(frame::toSrgb(c.x()), frame::toSrgb(c.y()), frame::toSrgb(c.z()));
}

Frame frameOf(const StreakView& view, const scene::RainDesc& desc, const Vec3& velocity) {
  Frame f{};
  const scene::Mat4& c = view.camera.projView;
  const float sx = 0.5f * static_cast<float>(view.width);
  const float sy = 0.5f * static_cast<float>(view.height);
  for (int col = 0; col < 4; ++col) {
    f.m[0][col] = (c(0, col) + c(3, col)) * sx;
    f.m[1][col] = (c(1, col) + c(3, col)) * sy;
    f.m[2][col] = (c(2, col) + c(3, col)) * 0.5f;
    f.m[3][col] = c(3, col);
  }
  f.dir = velocity * desc.exposure;
  f.along = f.apply(f.dir, 0);
  f.eye = view.camera.eye, f.right = view.camera.right;
  f.halfWidth = 0.5f * desc.dropWidth;
  auto rowNorm = [&](int r) { return Vec3(f.m[r][0], f.m[r][1], f.m[r][2]).norm(); };
  // 1% more than the bound, for rounding.
  f.marginX = 1.01f * f.halfWidth * rowNorm(0);
  f.marginY = 1.01f * f.halfWidth * rowNorm(1);
  f.marginW = 1.01f * f.halfWidth * rowNorm(3);
  f.width = view.width, f.height = view.height;
  return f;
}

// Rows [first, end) that the streaks of the `count` (<= 16) drops from `heads` may cover, from
// their two ends alone (a superset: a band finds the exact ones); end <= first when a streak is
// wholly outside the viewport. 16 drops at a time in SIMD lanes (the floors after them: GCC
// vectorises none without -fno-trapping-math).
void roughRows(const Frame& f, const Vec3* heads, int count, int* first, int* end) {
  constexpr int kLanes = 16;
  alignas(64) float hx[kLanes], hy[kLanes], hz[kLanes], yLo[kLanes], yHi[kLanes];
  alignas(64) int state[kLanes];  // 0: outside, 1: every row (a corner at or behind the eye), 2
  for (int k = 0; k < kLanes; ++k) {
    const Vec3& p = heads[std::min(k, count - 1)];
    hx[k] = p.x(), hy[k] = p.y(), hz[k] = p.z();
  }
  const float mW = f.marginW, mX = f.marginX, mY = f.marginY;
  const float width = static_cast<float>(f.width), height = static_cast<float>(f.height);
#pragma omp simd
  for (int k = 0; k < kLanes; ++k) {
    const float hX = applyRow(f.m[0], hx[k], hy[k], hz[k]);
    const float hY = applyRow(f.m[1], hx[k], hy[k], hz[k]);
    const float hW = applyRow(f.m[3], hx[k], hy[k], hz[k]);
    const float tX = hX - f.along.x, tY = hY - f.along.y, tW = hW - f.along.w;
    const bool behind = std::max(hW, tW) + mW <= 0;       // every corner behind the eye
    const bool straddles = !(std::min(hW, tW) - mW > 0);  // a corner may be at or behind it
    // A corner (X' + dx) / (W + dw) is within (|dx| + |x| |dw|) / (W - |dw|) of x = X' / W.
    const float rh = 1 / hW, rmh = 1 / (hW - mW), rt = 1 / tW, rmt = 1 / (tW - mW);
    const float xh = hX * rh, yh = hY * rh, xt = tX * rt, yt = tY * rt;
    const float mxh = (mX + std::abs(xh) * mW) * rmh, myh = (mY + std::abs(yh) * mW) * rmh;
    const float mxt = (mX + std::abs(xt) * mW) * rmt, myt = (mY + std::abs(yt) * mW) * rmt;
    const float xLo = std::min(std::min(1e30f, xh - mxh), xt - mxt);
    const float xHi = std::max(std::max(-1e30f, xh + mxh), xt + mxt);
    yLo[k] = std::min(std::min(1e30f, yh - myh), yt - myt);
    yHi[k] = std::max(std::max(-1e30f, yh + myh), yt + myt);
    const bool in = (xHi >= 0) & (xLo <= width) & (yHi[k] >= 0) & (yLo[k] <= height);
    const int b = behind, st = straddles, i = in;  // ints, so that the loop vectorises
    state[k] = (1 - b) * (st + (1 - st) * 2 * i);
  }
  for (int k = 0; k < count; ++k) {
    first[k] = 0, end[k] = state[k] == 1 ? f.height : 0;
    if (state[k] != 2) continue;
    first[k] = floorToInt(yLo[k] - 1, 0, f.height);
    end[k] = floorToInt(yHi[k] + 2, 0, f.height);
  }
}

// One streak, set up for its rows: the pixels whose centre (x, y) lies in the quad, clipped to
// near..far. The quad is O + u A + v B (u across, v along, both in [0, 1]) in window-homogeneous
// coordinates, so (x W, y W, W) = G (u, v, 1) with G's columns A, B, O (the X', Y', W rows), and
// adj(G) (x, y, 1) = det(G) / W (u, v, 1): GL's perspective-correct interpolation of the streak
// image coordinates, exactly, whichever of the two triangles a pixel is in. Its rows are also
// the quad's edges: u = 0, u = 1, v = 0, v = 1.
struct Streak {
  float uvd[3][3];  // adj(G): (x, y, 1) -> (nu, nv, nd), u = nu / nd, v = nv / nd
  float sign;       // of det(G): nd sign > 0 in front of the eye
  float depth[3];   // window depth = depth . (x, y, 1), affine over the quad's plane
  float leftP[4], leftQ[4], rightP[4], rightQ[4];  // x >= leftP + leftQ y, x < rightP + rightQ y
  float xMin, xMax, yMin, yMax;                    // bounding box, pixels
};

// Clips a convex polygon in window-homogeneous coordinates by `inside(p) >= 0`.
template <class Plane>
int clipPolygon(const Vec4f* in, int n, Vec4f* out, Plane inside) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const Vec4f& a = in[i];
    const Vec4f& b = in[(i + 1) % n];
    const float da = inside(a), db = inside(b);
    if (da >= 0) out[m++] = a;
    if ((da >= 0) != (db >= 0)) out[m++] = a + (b - a) * (da / (da - db));
  }
  return m;
}

// Half the streak's width, transformed: halfWidth along cross(head - tail, eye - middle), or
// along the camera's right when that vanishes (shaders/rain.vert).
Vec4f halfWidthOf(const Frame& f, const Vec3& head) {
  Vec3 side = f.dir.cross(f.eye - (head - 0.5f * f.dir));
  const float length = side.norm();
  side = length > 1e-12f ? Vec3(side * (f.halfWidth / length)) : Vec3(f.right * f.halfWidth);
  return f.apply(side, 0);
}

// Sets up the streak of the drop at `head`; false if it covers no pixel of the viewport.
// Mirrors shaders/rain.vert: the quad from tail to head, halfWidth either side along
// cross(head - tail, eye - middle), or along the camera's right when that vanishes.
bool setUp(const Frame& f, const Vec3& head, Streak& s) {
  const Vec4f h = f.apply(head, 1), t = h - f.along;
  const Vec4f half = halfWidthOf(f, head);
  const Vec4f o = t - half, a = half * 2, b = f.along;
  Vec4f poly[8] = {o, o + a, h + half, o + b};
  int n = 4;
  bool clipped = false;
  for (int k = 0; k < 4; ++k) clipped = clipped || !(poly[k].z >= 0 && poly[k].z <= poly[k].w);
  if (clipped) {  // through the near or far plane (0 <= Z' <= W): clip as GL does
    Vec4f kept[8];
    n = clipPolygon(poly, n, kept, [](const Vec4f& p) { return p.z; });
    n = clipPolygon(kept, n, poly, [](const Vec4f& p) { return p.w - p.z; });
    if (n < 3) return false;
  }
  s.xMin = s.yMin = 1e30f, s.xMax = s.yMax = -1e30f;
  for (int k = 0; k < n; ++k) {
    if (!(poly[k].w > 0)) return false;  // clipped at the near plane, so only on a degenerate
    const float r = 1 / poly[k].w;
    const float x = poly[k].x * r, y = poly[k].y * r;
    s.xMin = std::min(s.xMin, x), s.xMax = std::max(s.xMax, x);
    s.yMin = std::min(s.yMin, y), s.yMax = std::max(s.yMax, y);
  }
  if (!(s.xMax >= 0 && s.xMin <= static_cast<float>(f.width) && s.yMax >= 0 &&
        s.yMin <= static_cast<float>(f.height)))
    return false;
  const float g[3][3] = {{a.x, b.x, o.x}, {a.y, b.y, o.y}, {a.w, b.w, o.w}};
  float(&m)[3][3] = s.uvd;
  m[0][0] = g[1][1] * g[2][2] - g[1][2] * g[2][1];
  m[0][1] = g[0][2] * g[2][1] - g[0][1] * g[2][2];
  m[0][2] = g[0][1] * g[1][2] - g[0][2] * g[1][1];
  m[1][0] = g[1][2] * g[2][0] - g[1][0] * g[2][2];
  m[1][1] = g[0][0] * g[2][2] - g[0][2] * g[2][0];
  m[1][2] = g[0][2] * g[1][0] - g[0][0] * g[1][2];
  m[2][0] = g[1][0] * g[2][1] - g[1][1] * g[2][0];
  m[2][1] = g[0][1] * g[2][0] - g[0][0] * g[2][1];
  m[2][2] = g[0][0] * g[1][1] - g[0][1] * g[1][0];
  const float det = g[0][0] * m[0][0] + g[0][1] * m[1][0] + g[0][2] * m[2][0];
  if (!(std::abs(det) > 0)) return false;  // seen edge-on: no area, as GL draws nothing
  s.sign = det > 0 ? 1.0f : -1.0f;
  for (int j = 0; j < 3; ++j) s.depth[j] = (a.z * m[0][j] + b.z * m[1][j] + o.z * m[2][j]) / det;
  // The edges u >= 0, u <= 1, v >= 0, v <= 1 as sign (e . (x, y, 1)) >= 0; an edge with e_x ~ 0
  // is the top or bottom, which [yMin, yMax] bounds.
  const float edges[4][3] = {{m[0][0], m[0][1], m[0][2]},
                             {m[2][0] - m[0][0], m[2][1] - m[0][1], m[2][2] - m[0][2]},
                             {m[1][0], m[1][1], m[1][2]},
                             {m[2][0] - m[1][0], m[2][1] - m[1][1], m[2][2] - m[1][2]}};
  for (int k = 0; k < 4; ++k) {
    const float ex = s.sign * edges[k][0], ey = s.sign * edges[k][1], e0 = s.sign * edges[k][2];
    s.leftP[k] = -1e30f, s.leftQ[k] = 0, s.rightP[k] = 1e30f, s.rightQ[k] = 0;
    if (!(std::abs(ex) > 1e-6f * std::abs(ey))) continue;
    const float p = -e0 / ex, q = -ey / ex;  // x on the edge at y
    if (ex > 0) {
      s.leftP[k] = p, s.leftQ[k] = q;
    } else {
      s.rightP[k] = p, s.rightQ[k] = q;
    }
  }
  return true;
}

// One row of a streak: y of its pixel centres, the covered pixels [x0, x1), and the parts of
// the homography and depth that depend on y alone.
struct Row {
  float y, du, dv, dd, dz;
  int x0, x1;
};
inline Row rowOf(const Streak& s, int row, float xLo, float xHi, int width) {
  Row r;
  r.y = static_cast<float>(row) + 0.5f;
  float left = xLo, right = xHi;
  for (int e = 0; e < 4; ++e) {
    left = std::max(left, s.leftP[e] + s.leftQ[e] * r.y);
    right = std::min(right, s.rightP[e] + s.rightQ[e] * r.y);
  }
  r.x0 = floorToInt(std::ceil(left - 0.5f), 0, width);
  r.x1 = floorToInt(std::ceil(right - 0.5f), 0, width);
  r.du = s.uvd[0][1] * r.y + s.uvd[0][2], r.dv = s.uvd[1][1] * r.y + s.uvd[1][2];
  r.dd = s.uvd[2][1] * r.y + s.uvd[2][2], r.dz = s.depth[1] * r.y + s.depth[2];
  return r;
}

// The streak's alpha at pixel x of row r; 0, and keep false, where x is not covered, is outside
// near..far or behind the eye, or is not nearer than the frame (`frameDepth`). `image`: the
// drop's streak image padded by its edge texels (pw texels a row), `fw` x `fh` unpadded.
inline float fragmentAlpha(const Streak& s, const Row& r, int x, float frameDepth,
                           const float* image, int pw, float fw, float fh, bool& keep) {
  const float px = static_cast<float>(x) + 0.5f;
  const float nd = s.uvd[2][0] * px + r.dd;
  const float z = s.depth[0] * px + r.dz;
  keep = x >= r.x0 && x < r.x1 && nd * s.sign > 0 && z >= 0 && z <= 1 && z < frameDepth;
  const float w = 1 / (keep ? nd : 1.0f);
  // In [0, 1], and 0 for a NaN (a subnormal nd), which std::clamp would pass on to the index.
  const auto unit = [](float t) { return t > 0 ? std::min(t, 1.0f) : 0.0f; };
  const float u = unit((s.uvd[0][0] * px + r.du) * w);
  const float v = unit((s.uvd[1][0] * px + r.dv) * w);
  // GL_LINEAR with GL_CLAMP_TO_EDGE, on the padded image.
  const float ts = u * fw + 0.5f, tt = v * fh + 0.5f;  // padded texel space, >= 0.5
  const int s0 = static_cast<int>(ts), t0 = static_cast<int>(tt);
  const float ws = ts - static_cast<float>(s0), wt = tt - static_cast<float>(t0);
  const int i = t0 * pw + s0;
  const float a0 = image[i] + ws * (image[i + 1] - image[i]);
  const float a1 = image[i + pw] + ws * (image[i + pw + 1] - image[i + pw]);
  return keep ? a0 + wt * (a1 - a0) : 0.0f;
}

}  // namespace

StreakRaster::StreakRaster(const scene::RainDesc& desc, StreakImages images)
    : desc_(desc), images_(std::move(images)) {
  // Each image with a border of copies of its edge texels: bilinear filtering with
  // GL_CLAMP_TO_EDGE then needs no clamping of texel indices.
  const int w = images_.width, h = images_.height, pw = w + 2, ph = h + 2;
  alpha_.resize(static_cast<std::size_t>(images_.layers) * pw * ph);
  for (int l = 0; l < images_.layers; ++l)
    for (int row = 0; row < ph; ++row)
      for (int column = 0; column < pw; ++column)
        alpha_[(static_cast<std::size_t>(l) * ph + row) * pw + column] =
            images_.at(l, std::clamp(row - 1, 0, h - 1), std::clamp(column - 1, 0, w - 1)) / 255.0f;
  // The level of detail's lines: each padded row of each image averaged across its width.
  profile_.assign(static_cast<std::size_t>(images_.layers) * ph, 0.0f);
  for (int l = 0; l < images_.layers; ++l)
    for (int row = 0; row < ph; ++row) {
      float sum = 0;
      for (int column = 0; column < w; ++column)
        sum += alpha_[(static_cast<std::size_t>(l) * ph + row) * pw + column + 1];
      profile_[static_cast<std::size_t>(l) * ph + row] = sum / static_cast<float>(w);
    }
  // The far tier's sums (rain.far_tier "sums"): the images' means along and across.
  sums_.setImages(alpha_, profile_, images_.layers, w, h);
}

void StreakRaster::draw(const StreakView& view, const StreakDrops& drops, const Vec3& unlit,
                        const float* depth) {
  width_ = view.width, height_ = view.height;
  layer_.resize(4 * static_cast<std::size_t>(width_) * height_);
  const std::vector<Vec3>& heads = *drops.positions;
  const std::vector<std::uint8_t>& layers = *drops.layers;
  const std::size_t n = heads.size();
  const Frame f = frameOf(view, desc_, drops.velocity);
  const int rowsPerBand = kRowsPerBand;
  const int bandCount = std::max(1, (height_ + rowsPerBand - 1) / rowsPerBand);

  // 1. The colours: eq. (13), texture x light colour x intensity inside the cone, the unlit
  // tint outside, sRGB-encoded as the frame is.
  const Vec3 unlitSrgb = toSrgb(unlit);
  const std::optional<scene::SpotlightDesc>& light = desc_.spotlight;
  const Vec3 litSrgb = light ? toSrgb(light->colour * light->intensity) : unlitSrgb;
  auto colourOf = [&](const Vec3& head) {
    if (!light) return unlitSrgb;
    const float w = sph::rain::spotlightWeight(*light, head);
    if (w == 0) return unlitSrgb;
    if (w == 1) return litSrgb;
    return toSrgb(unlit + w * (light->colour * light->intensity - unlit));
  };
  // No depth test: a frame that is all far plane.
  if (depth == nullptr) {
    farDepth_.assign(static_cast<std::size_t>(width_) * height_, 2.0f);
    depth = farDepth_.data();
  }
  const float* const frameDepth = depth;

  // 2. Bin the drops by the bands of rows they may cover: each thread its contiguous share of
  // the drops, so that bins taken in thread order are in drop order. With rain.far_tier "sums"
  // the far tier's lines are added to the sums here, in one pass over the drops, and only the
  // other drops are binned, to be drawn over it.
  const bool lod = desc_.lodWidth > 0;
  const bool sumsTier = lod && desc_.farTier == scene::RainFarTier::Sums;
  // The bands draw lines only in the lines tier: with the sums every line was added to them
  // already, and the bands hold only the exact streaks (no set-up to do for them).
  const bool lineTier = lod && !sumsTier;
  const int maxThreads = omp_get_max_threads();
  bins_.resize(static_cast<std::size_t>(maxThreads) * bandCount);
  for (auto& bin : bins_) bin.clear();
  if (sumsTier) sums_.begin(width_, height_, frameDepth, maxThreads);
  int threads = 1;
  std::uint64_t farFragments = 0;
#pragma omp parallel num_threads(maxThreads) reduction(+ : farFragments)
  {
    const int thread = omp_get_thread_num(), count = omp_get_num_threads();
    if (thread == 0) threads = count;
    const std::size_t begin = n * static_cast<std::size_t>(thread) / count;
    const std::size_t end = n * static_cast<std::size_t>(thread + 1) / count;
    std::vector<std::uint32_t>* bins = bins_.data() + static_cast<std::size_t>(thread) * bandCount;
    for (std::size_t group = begin; group < end; group += 16) {
      const int lanes = static_cast<int>(std::min<std::size_t>(16, end - group));
      Lines lines;
      if (sumsTier) {
        std::uint32_t index[Lines::kLanes];
        for (int k = 0; k < lanes; ++k) index[k] = static_cast<std::uint32_t>(group + k);
        setUpLines(f, heads, index, lanes, desc_.lodWidth, lines);
        Vec3 colours[Lines::kLanes];
        float alphas[Lines::kLanes];
        for (int k = 0; k < lanes; ++k) {
          const std::size_t i = group + k;
          colours[k] = colourOf(heads[i]);
          alphas[k] = lines.coverage[k] * sums_.meanAlong(layers[i]);
        }
        farFragments += sums_.addLines(thread, lines, lanes, colours, alphas);
        // Wider than a pixel: lines side by side across the row's extent.
        bool exact = false;
        for (int k = 0; k < lanes; ++k) {
          exact = exact || !lines.ok[k];
          if (!lines.ok[k] || lines.coverage[k] <= 1 || lines.end[k] <= lines.first[k]) continue;
          farFragments += sums_.addWide(thread, lines[k], lines.first[k], lines.end[k], colours[k],
                                        layers[group + k]);
        }
        if (!exact) continue;  // every drop of the group is in the sums: none to bin
      }
      int first[16], last[16];
      roughRows(f, heads.data() + group, lanes, first, last);
      for (int k = 0; k < lanes; ++k) {
        if (last[k] <= first[k] || (sumsTier && lines.ok[k])) continue;
        for (int band = first[k] / rowsPerBand; band <= (last[k] - 1) / rowsPerBand; ++band)
          bins[band].push_back(static_cast<std::uint32_t>(group + k));
      }
    }
  }
  if (sumsTier) sums_.resolve(layer_.data());

  // 3. The bands, each walking its drops in order (with the sums: the drops not in them, over
  // them); several per thread so that uneven bands even out (which thread takes which band
  // changes no pixel).
  const int pw = images_.width + 2, ph = images_.height + 2;  // alpha_: padded
  const float fw = static_cast<float>(images_.width), fh = static_cast<float>(images_.height);
  bands_.resize(static_cast<std::size_t>(maxThreads));
  constexpr int kChunk = 16;
  std::uint64_t fragments = farFragments;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : fragments)
  for (int band = 0; band < bandCount; ++band) {
    const int bandFirst = band * rowsPerBand, bandEnd = std::min(height_, bandFirst + rowsPerBand);
    StreakBand& b = bands_[static_cast<std::size_t>(omp_get_thread_num())];
    if (sumsTier) {
      // Only drops of no line are in the bins, drawn over the sums; a band without any keeps the
      // sums' pixels as resolve() wrote them.
      bool any = false;
      for (int thread = 0; thread < threads; ++thread)
        any = any || !bins_[static_cast<std::size_t>(thread) * bandCount + band].empty();
      if (!any) continue;
    }
    b.begin(bandFirst, bandEnd, width_, frameDepth, sumsTier ? layer_.data() : nullptr);
    float* const out = b.layer();
    const float* const bandDepth = b.depth();
    for (int thread = 0; thread < threads; ++thread) {
      const std::vector<std::uint32_t>& bin =
          bins_[static_cast<std::size_t>(thread) * bandCount + band];
      for (std::size_t group = 0; group < bin.size(); group += Lines::kLanes) {
        const int count =
            static_cast<int>(std::min<std::size_t>(Lines::kLanes, bin.size() - group));
        Lines lines;
        if (lineTier) setUpLines(f, heads, bin.data() + group, count, desc_.lodWidth, lines);
        for (int lane = 0; lane < count; ++lane) {
          const std::uint32_t i = bin[group + lane];
          if (lineTier && lines.ok[lane]) {
            const int first = std::max(bandFirst, lines.first[lane]),
                      end = std::min(bandEnd, lines.end[lane]);
            if (end <= first) continue;
            const Vec3 c = colourOf(heads[i]);
            const float* p = profile_.data() + static_cast<std::size_t>(layers[i]) * ph;
            fragments += drawLineRows(lines[lane], first, end, b, c, p, fh, simd_);
            continue;
          }
          Streak s;
          if (!setUp(f, heads[i], s)) continue;
          const int first = std::max(bandFirst, floorToInt(std::ceil(s.yMin - 0.5f), 0, height_));
          const int end = std::min(bandEnd, floorToInt(std::ceil(s.yMax - 0.5f), 0, height_));
          if (end <= first) continue;
          const Vec3 c = colourOf(heads[i]);
          const float* image = alpha_.data() + static_cast<std::size_t>(layers[i]) * pw * ph;
          const float xLo = std::max(s.xMin, -1.0f);
          const float xHi = std::min(s.xMax, static_cast<float>(width_) + 1);
          // Rows in chunks: a vectorised pass takes each row's first candidate pixel (the only one
          // of most streaks, under a pixel wide), then the blends and any further pixels of wider
          // rows. Pixel centres x + 0.5 in [x0, x1) are covered; one candidate is taken even where
          // a row has none (masked, alpha 0) rather than a branch per row: whether a row of a thin
          // streak holds a pixel centre is a coin toss to the branch predictor.
          for (int chunkFirst = first; chunkFirst < end; chunkFirst += kChunk) {
            const int rows = std::min(kChunk, end - chunkFirst);
            alignas(64) float alphas[kChunk];
            alignas(64) int pixels[kChunk], xs[kChunk], wider[kChunk];
            int covered = 0;
#pragma omp simd reduction(+ : covered)
            for (int k = 0; k < rows; ++k) {
              const Row r = rowOf(s, chunkFirst + k, xLo, xHi, width_);
              const int x = std::min(r.x0, width_ - 1);
              const int pixel = b.at(x, chunkFirst + k);
              bool keep = false;
              alphas[k] = fragmentAlpha(s, r, x, bandDepth[pixel], image, pw, fw, fh, keep);
              covered += keep;
              pixels[k] = pixel, xs[k] = x;
              wider[k] = r.x1 - x - 1;
            }
            fragments += static_cast<std::uint64_t>(covered);
            for (int k = 0; k < rows; ++k)
              blendOver(out + 4 * static_cast<std::size_t>(pixels[k]), c, alphas[k]);
            for (int k = 0; k < rows; ++k) {
              if (wider[k] <= 0) continue;
              const Row r = rowOf(s, chunkFirst + k, xLo, xHi, width_);
              for (int x = xs[k] + 1; x < r.x1; ++x) {
                const int pixel = b.at(x, chunkFirst + k);
                bool keep = false;
                const float alpha =
                    fragmentAlpha(s, r, x, bandDepth[pixel], image, pw, fw, fh, keep);
                fragments += keep;
                blendOver(out + 4 * static_cast<std::size_t>(pixel), c, alpha);
              }
            }
          }
        }
      }
    }
    b.store(layer_.data());
  }
  fragments_ = fragments;
}

}  // namespace sph::render::rain
