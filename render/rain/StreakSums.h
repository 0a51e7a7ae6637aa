// The far tier drawn as sums (rain.far_tier "sums", docs/rain.md, "Level of detail"): the
// streaks narrower than rain.lod_width pixels, whose lines (render/rain/StreakLine.h) cost a
// read-modify-write of the layer in every row - ~20 M rows a frame at 1,000,000 drops, most of
// the raster. Here a line is added once per column it crosses instead: +v at the row where its
// run in that column starts and -v at the row where it ends, into a frame-sized buffer of
// integers whose running sums down each column then give every pixel the sum of the lines over
// it. Rain falls nearly straight down, so a line is one run (one column) or a few: the cost is
// per drop, and per pixel once for the sums.
//
// What a pixel gets: with b_i = -ln(1 - a_i) for the lines i over it (a_i: the line's alpha, its
// coverage times its streak image's mean along the length - constant along the line), T = exp(-sum
// b_i) = prod (1 - a_i), the transmittance that blending them in any order gives, and L = (sum c_i
// b_i / sum b_i) (1 - T): their colours weighted by b_i. One line: L = c a, exactly "over". Lines
// of one colour: exactly what blending them in any order gives. Lines of different colours over one
// pixel (a spotlight's rim): the colour is their weighted mean where "over" weights the last
// blended most - the drop order within the tier is lost. The tier is composed behind the exact
// streaks (their bands start from it), which are the wider, nearer ones.
//
// The sums are integers (fixed point, 2^-18), so they do not depend on the order they are added in:
// the layer is the same bit for bit for any thread count. A run is not added into a frame-sized
// buffer where it falls - two scattered read-modify-writes of 16 bytes a drop into megabytes,
// each a cache miss (docs/notes/2026-11-27-rain-respawn-and-sums.md, "The far tier as sums") -
// but written, in the order the
// thread sets it up, to a list per strip of 32 columns; resolve() then takes one strip at a time,
// adds its runs into a strip-sized buffer that stays in the core's cache (16 bytes x 32 columns x
// the rows), and takes the running sums down its columns. No frame per thread: the memory is the
// runs (16 bytes each) and a strip per thread. The depth test is per pixel, as the lines': a run
// whose far end is nearer than every pixel of its column in the tiles of rows it spans is added
// whole, any other row by row against the frame's depth.
#pragma once

#include <cstdint>
#include <vector>

#include "render/rain/StreakLine.h"
#include "sim/Types.h"

namespace sph::render::rain {

class StreakSums {
 public:
  StreakSums();
  // The streak images as the raster holds them (StreakRaster.cpp): `alpha` each padded by its
  // edge texels, `profile` their padded rows averaged across; `w` x `h` unpadded.
  void setImages(const std::vector<float>& alpha, const std::vector<float>& profile, int layers,
                 int w, int h);
  // Image `layer`'s mean along the streak, as the lines fetch it: a line's alpha is its coverage
  // times this.
  float meanAlong(int layer) const { return meanAlong_[static_cast<std::size_t>(layer)]; }
  // Starts a frame of width x height pixels for up to `threads` threads adding lines; `depth`:
  // the frame's window depth (row-major, row 0 at the bottom), a line's row is kept where it is
  // nearer (GL_LESS). Not in a parallel region (it runs its own).
  void begin(int width, int height, const float* depth, int threads);
  // Thread `thread` adds rows [first, end) of `line` in colour `c` (sRGB-encoded) at `alpha` a
  // row; returns the rows that passed the depth test (the fragments).
  std::uint64_t add(int thread, const Line& line, int first, int end, const Vec3& c, float alpha);
  // Thread `thread` adds the lines of the `count` lanes of `lines` that are `ok` and at most a
  // pixel wide, lane k in colour `colour[k]` at `alpha[k]` a row: add() for each, with the lines
  // in one column and nearer than the frame there - most of them - taken as one run without
  // add()'s search for the columns. Returns the fragments.
  std::uint64_t addLines(int thread, const Lines& lines, int count, const Vec3* colour,
                         const float* alpha);
  // Thread `thread` adds rows [first, end) of `line`, `line.coverage` (1 to 8) pixels wide, in
  // image `layer`: ceil(coverage) lines side by side across the row's extent, each with its
  // strip of the image across; returns the fragments.
  std::uint64_t addWide(int thread, const Line& line, int first, int end, const Vec3& c, int layer);
  // Adds all threads' runs strip by strip, takes the running sums down the columns and writes
  // every pixel's (L, T) into `layer` (row-major, 4 floats a pixel; (0, 0, 0, 1) where no line
  // is); the runs are dropped for the next frame. Not in a parallel region (it runs its own).
  void resolve(float* layer);
  // Runs the last frame added (before resolve()): what its lists held.
  std::size_t runs() const { return runs_; }
  // Runs the lists have room for now, all threads and strips (their memory: 16 bytes a run).
  std::size_t runCapacity() const;

 private:
  static constexpr int kTileRows = 64;  // rows of a tile of the nearest depth per column
  // Columns of a strip: its buffer (16 bytes x 32 x 540 rows: 270 KiB at 960 x 540) stays in a
  // core's L2 while its runs are added and summed; a strip's row is 512 bytes of the layer.
  static constexpr int kStrip = 32;
  // A run of rows [first, end) of column x of its strip, adding v: 16 bytes, packed, since
  // writing and reading the runs is most of the tier's memory traffic. lo: v[0], v[1], v[2] 21
  // bits each; hi: v[3] 21 bits, x 5, first 16, end 16 (end = height: down to the last row). Each
  // v[k] fits: b is at most -ln(0.01) = 4.61, 1,207,200 in units of 2^-18 (< 2^21), and the
  // colours are sRGB-encoded, in [0, 1]; frames are under 65,536 rows (begin() checks).
  struct Run {
    std::uint64_t lo, hi;
  };
  static constexpr int kValueBits = 21;
  static_assert(kStrip == 32, "a run keeps its column in the strip in 5 bits");
  void addRun(int thread, int column, int first, int end, const std::int32_t* v);
  // v = (c.r b, c.g b, c.b b, b) in fixed point, b = -ln(1 - alpha); false if b rounds to 0.
  bool valueOf(const Vec3& c, float alpha, std::int32_t* v) const;
  // The runs, [thread * strips + strip], in the order the thread added them.
  std::vector<std::vector<Run>> lists_;
  // Per thread of resolve(): a strip's sums, kStrip x height x 4, kept all zero between strips.
  std::vector<std::vector<std::int32_t>> strips_;
  std::vector<float> meanAlong_;  // per image
  // The streaks k = 1..kMaxStrips pixels wide: per image, the mean of strip j of k across it at
  // [k (k - 1) / 2 + j], scaled so that the k strips' mean is meanAlong_ (the same light).
  static constexpr int kMaxStrips = 8, kStripTable = kMaxStrips * (kMaxStrips + 1) / 2;
  std::vector<float> stripMean_;
  std::vector<float> weights_;  // -ln(1 - a) at a = i / kWeights, for valueOf()
  std::vector<float> nearest_;  // [tile][column]: the nearest frame depth in the tile's rows
  const float* depth_ = nullptr;
  int width_ = 0, height_ = 0, threads_ = 0, stripCount_ = 0;
  std::size_t runs_ = 0;
};

}  // namespace sph::render::rain
