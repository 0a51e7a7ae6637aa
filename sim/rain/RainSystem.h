// View-dependent rain (seed 002, Im & Sung 2021; docs/rain.md): a constant budget of drops that
// fall with the wind and are respawned, the moment they leave the rain space or hit a solid or the
// water, at a random point of the current rain space. Three spawn models (RainDesc::spawn): the
// paper's view space and the two baselines it compares against. No GL: render/rain/ draws it.
#pragma once

#include <cstdint>
#include <unordered_set>
#include <vector>

#include "sim/rain/EyeDepth.h"
#include "sim/rain/RainRandom.h"
#include "sim/rain/RainSpace.h"
#include "sim/rain/ViewSampler.h"
#include "sim/scene/RainDesc.h"
#include "sim/scene/Solid.h"

namespace sph::rain {

// The cells (edge `cell` m) that hold at least one fluid particle: the water a drop stops in.
class WaterCells {
 public:
  WaterCells(const std::vector<Vec3>& fluid, float cell);
  // The cells of `keys` (keyOf's, with the same `cell`; repeats allowed): the union of the cells
  // several parts of the fluid occupy (an MPI run's ranks, job/distributed/CollectiveCacheSink.h)
  // is the set the whole fluid gives.
  static WaterCells fromKeys(const std::vector<std::uint64_t>& keys, float cell);
  // The key of the cell that holds `p`.
  static std::uint64_t keyOf(const Vec3& p, float cell);
  bool contains(const Vec3& p) const;
  float cell() const { return cell_; }
  // Whether the segment from a to b may meet a cell: false when their bounding boxes are apart.
  bool near(const Vec3& a, const Vec3& b) const;
  std::size_t size() const { return cells_.size(); }
  // The occupied cells' keys, ascending.
  std::vector<std::uint64_t> keys() const;
  // Calls f(corner) with the lowest corner of every occupied cell, in no particular order.
  template <class F>
  void forEachCorner(F f) const {
    for (std::uint64_t k : cells_) f(cornerOf(k, cell_));
  }
  // The lowest corner of the cell of key `k` (keyOf's inverse).
  static Vec3 cornerOf(std::uint64_t k, float cell);

 private:
  explicit WaterCells(float cell) : cell_(cell) {}
  std::uint64_t key(const Vec3& p) const { return keyOf(p, cell_); }
  float cell_;
  std::unordered_set<std::uint64_t> cells_;
  Aabb bounds_;  // of the cells' corners
};

// What stops a drop besides leaving the rain space.
struct RainObstacles {
  const std::vector<scene::Solid>* solids = nullptr;
  const WaterCells* water = nullptr;
};

// sampling "paper": a point of the ball of radius 1 about the origin as eq. (6)-(7) read
// literally, a separate random radius per axis, from five uniform numbers u0..u4 (eq. (6)'s
// theta and phi, then the radii of x, y and z). Not uniform (docs/rain.md). The default sampling,
// "uniform", is sim/rain/ViewSampler.h.
Vec3 paperBallPoint(const float u[5]);

bool insideSolid(const Vec3& p, const std::vector<scene::Solid>& solids);
// The first point of the segment from a to b inside one of the solids: its share of the way
// (Solid::segmentEntry), > 1 when there is none.
float firstSolidEntry(const Vec3& a, const Vec3& b, const std::vector<scene::Solid>& solids);

struct RainCounters {
  std::uint64_t leftSpace = 0, hitSolid = 0, hitWater = 0;  // respawns by cause, cumulative
  // Respawns of drops still in the rain space that a solid or the water hides from the eye
  // (rain.occlusion "depth_map": sim/rain/EyeDepth.h), counted after the causes above.
  std::uint64_t hidden = 0;
  std::uint64_t rejected = 0;       // sphere samples the side planes refused (eq. (8)-(9))
  std::uint64_t outsideSphere = 0;  // sampling "uniform": candidates of the cube outside the sphere
  std::uint64_t accepted = 0;       // spawns
  // Spawns that found no free place in kMaxTries candidates (RainSystem.cpp) and parked the drop
  // at the centre of the space (the box, the region), where it falls until it leaves or hits
  // something: many drops on one point, which the share in view cannot see. `uniform` view
  // drops draw from the cube or the pyramid, whichever holds the rain space best, so this stays
  // 0 at any field of view unless the obstacles fill nearly all of it; `paper` sampling (eq. (7)
  // from the whole sphere) still parks at 1-2 degrees.
  std::uint64_t parked = 0;
};

class RainSystem {
 public:
  // `aspect`: the viewport's width / height (the rain camera's frustum).
  RainSystem(const scene::RainDesc& desc, float aspect);

  // Places every drop at random in the spawn volume of `camera` (the first frame).
  void reset(const scene::CameraDesc& camera, const RainObstacles& obstacles = {});
  // Moves the drops by dt (s) and respawns those that left the spawn volume of `camera` (which
  // may have moved since the last call) or hit an obstacle.
  void update(const scene::CameraDesc& camera, float dt, const RainObstacles& obstacles = {});
  // Takes over drops as a run left them (a resume from the cache, io/cache/RainCache.h): positions
  // and respawn counts per drop (as many as the budget), the rain camera of that moment. Counters
  // start again from 0.
  void restore(const scene::CameraDesc& camera, const std::vector<Vec3>& positions,
               const std::vector<std::uint32_t>& generations);

  const scene::RainDesc& desc() const { return desc_; }
  const RainSpace& space() const { return space_; }
  std::size_t size() const { return positions_.size(); }
  const std::vector<Vec3>& positions() const { return positions_; }
  // Per drop: which streak image (array texture layer) it shows.
  const std::vector<std::uint8_t>& layers() const { return layers_; }
  // Per drop: how often it has been respawned (with the seed and its index, all that decides
  // where it is placed next).
  const std::vector<std::uint32_t>& generations() const { return generations_; }
  Vec3 velocity() const { return desc_.wind + Vec3(0, -desc_.fallSpeed, 0); }
  const RainCounters& counters() const { return counters_; }
  // rain.feed_fluid only (else always empty): where the drops that landed in the water during
  // the last update() entered it, in drop order - the first point of each drop's path over that
  // update inside a water cell and outside the solids (sim/rain/RainFeed.h).
  const std::vector<Vec3>& landings() const { return landings_; }
  // Whether p is where this spawn model keeps drops (rain space, camera box or region).
  bool inSpawnVolume(const Vec3& p) const;
  // The depth image of the solids and the water from the rain camera of the last reset or
  // update (spawn "view" with rain.occlusion "depth_map" and obstacles given; else inactive).
  const EyeDepth& eyeDepth() const { return eyeDepth_; }
  // Edge (m) of the camera-following cube of spawn "box": the rain space's volume.
  float boxEdge() const { return boxEdge_; }

 private:
  // The rain camera of `camera`, and the depth image of `obstacles` from it where drops are kept
  // only where the eye sees them.
  void setCamera(const scene::CameraDesc& camera, const RainObstacles& obstacles);
  // Whether a drop at p may be placed or kept there: outside the obstacles and seen by the eye.
  bool placeable(const Vec3& p, const RainObstacles& obstacles) const {
    return eyeDepth_.visible(p) && !blocked(p, obstacles);
  }
  // Draws drop i's position for its current generation, outside the obstacles; adds the
  // candidates it refused, and whether it parked, to `count`.
  void spawn(std::size_t i, const RainObstacles& obstacles, ViewSpawnCount& count);
  // Moves drops begin..end-1 by `step`; out[k] = 1 where drop begin + k left the spawn volume.
  void moveAndTest(std::size_t begin, std::size_t end, const Vec3& step, std::uint8_t* out);
  static bool blocked(const Vec3& p, const RainObstacles& obstacles);
  std::uint8_t layerOf(std::size_t i) const;
  std::uint8_t layerFrom(const DropRandom& u) const;  // layerOf with the drop's numbers
  // Whether the path from `from` to `to` enters a water cell outside the solids before the share
  // `upTo` of the way (where it enters a solid: it goes no further), and where it first does
  // (`entry`): sampled every quarter cell, `to` last. Over a frame interval a drop falls further
  // than a thin sheet of water is deep: testing `to` alone let it through.
  static bool entersWater(const Vec3& from, const Vec3& to, float upTo,
                          const RainObstacles& obstacles, Vec3& entry);

  scene::RainDesc desc_;
  float aspect_;
  RainSpace space_;
  EyeDepth eyeDepth_;
  float boxEdge_ = 0;
  float lastFov_ = -1;
  std::vector<Vec3> positions_;
  std::vector<std::uint32_t> generations_;
  std::vector<std::uint8_t> layers_;
  RainCounters counters_;
  std::vector<Vec3> landings_;
  std::vector<Vec3> entries_;      // feed_fluid: per drop, its entry point (where hit_ is 1)
  std::vector<std::uint8_t> hit_;  // feed_fluid: per drop, landed in the water this update
};

}  // namespace sph::rain
