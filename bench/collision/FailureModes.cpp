// How recall moves with the paper's four failure modes (seed 001, section 4.3): close-up against
// long shot, one-sided responses, occlusion, depth mismatch.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "bench/collision/Detection.h"
#include "bench/collision/Sections.h"
#include "bench/collision/Snapshot.h"
#include "sim/collision/Exact.h"

namespace sph::collisionbench {

void printModes(const Options& o) {
  const Snapshot snap = takeSnapshot('A', o.recallSize, o.warm);
  const Particles& p = snap.particles;
  const float range = snap.scene.collision->range;
  const std::vector<IdPair> truth = truePairs(p, range);
  scene::CollisionDesc own = paperCdt(snap.scene);
  own.positionSource = scene::CdtPositionSource::Particle;
  const scene::CameraDesc camera = *snap.scene.camera;
  const double distance = (camera.position - camera.target).norm();
  std::printf(
      "\n### Failure modes (density A, %zu particles, snapshot at t = %.2f s, %zu true pairs)\n",
      p.size(), o.warm, truth.size());

  // (1) Close-up vs long shot: the collision camera moved along its axis (eq. 1 offsets).
  std::printf(
      "\n**1. Close-up vs long shot** (collision camera `offset` along its z axis; scene camera "
      "%.1f m from the target)\n\n",
      distance);
  std::printf(
      "| offset (m) | distance (m) | range in texels | particles per texel | pair recall r=1 | "
      "particle recall r=1 | pair recall adaptive r | mean adaptive r |\n");
  std::printf("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  for (double factor : {0.4, 0.6, 1.0, 1.5, 2.5, 4.0}) {
    scene::CollisionDesc d = own;
    d.camera = scene::CdtCameraMode::Offset;
    d.offset = static_cast<float>((factor - 1.0) * distance);
    const CdtDetection fixed = detectCdt(d, camera, p, truth);
    scene::CollisionDesc a = d;
    a.adaptiveTexelRange = true;
    a.maxTexelRange = 8;
    const CdtDetection adaptive = detectCdt(a, camera, p, truth);
    const cdt::View& view = fixed.cdt->settings().view;
    std::size_t occupied = 0;
    for (const auto& t : fixed.cdt->texture().texels) occupied += t[3] >= 0;
    std::size_t onScreen = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
      onScreen += cdt::texelOf(view, p.x[i], p.y[i], p.z[i]).onScreen;
    const double texels = range * view.texelScale / (factor * distance);
    std::printf("| %+.2f | %.2f | %.2f | %.2f | %.3f | %.3f | %.3f | %.2f |\n", d.offset,
                factor * distance, texels,
                occupied ? static_cast<double>(onScreen) / occupied : 0.0,
                fixed.recall.pairRecall(), fixed.recall.particleRecall(),
                adaptive.recall.pairRecall(), adaptive.meanRange);
    std::fflush(stdout);
  }

  // (2) One-sided responses.
  std::printf(
      "\n**2. One-sided response** (a particle reacts to a partner that does not react to it)\n\n");
  std::printf(
      "| method | responding particles | of them one-sided | mutual pairs |\n| --- | ---: | ---: | "
      "---: |\n");
  auto oneSided = [&](const char* name, const collision::Recall& r,
                      const std::vector<std::uint32_t>& chosen) {
    std::map<std::uint32_t, std::uint32_t> partnerOf;
    for (std::size_t i = 0; i < p.size(); ++i) partnerOf[p.id[i]] = chosen[i];
    std::size_t mutual = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (chosen[i] != collision::kNone && partnerOf[chosen[i]] == p.id[i]) ++mutual;
    }
    std::printf("| %s | %zu | %.3f | %zu |\n", name, r.chosen, r.unansweredFraction(), mutual / 2);
  };
  {
    collision::ExactDetector exact;
    std::vector<std::uint32_t> partner;
    exact.detect(p.x.data(), p.y.data(), p.z.data(), p.size(), range, nullptr, partner, nullptr);
    std::vector<std::uint32_t> chosen(p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
      chosen[i] = partner[i] == collision::kNone ? collision::kNone : p.id[partner[i]];
    oneSided(enumName(scene::CollisionMethod::Exact),
             collision::measureRecall(truth, {}, p.id, chosen), chosen);
    for (int variant = 0; variant < 3; ++variant) {
      scene::CollisionDesc d = variant == 0 ? paperCdt(snap.scene) : own;
      if (variant == 2) d.layers = 4, d.adaptiveTexelRange = true;
      const CdtDetection det = detectCdt(d, camera, p, truth);
      for (std::size_t i = 0; i < p.size(); ++i) chosen[i] = det.cdt->diagnostics()[i].partner;
      oneSided(variant == 0   ? "cdt, paper"
               : variant == 1 ? "cdt, own position"
                              : "cdt, adaptive r + 4 layers",
               det.recall, chosen);
    }
  }

  // (3) Occlusion: pairs by how many of their two particles the texture's first layer shows.
  std::printf(
      "\n**3. Occlusion** (true pairs by how many of the two particles layer 0 of the texture "
      "holds)\n\n");
  {
    const CdtDetection one = detectCdt(own, camera, p, truth);
    std::set<std::uint32_t> visible;
    const auto& tex = one.cdt->texture();
    const std::size_t plane = static_cast<std::size_t>(tex.width) * tex.height;
    for (std::size_t t = 0; t < plane; ++t) {
      if (tex.texels[t][3] >= 0) visible.insert(static_cast<std::uint32_t>(tex.texels[t][3]));
    }
    std::printf("%zu of %zu particles (%.1f%%) are visible in layer 0.\n\n", visible.size(),
                p.size(), 100.0 * visible.size() / p.size());
    std::printf(
        "| layers | both visible | one hidden | both hidden | all pairs | cdt-cpu ms |\n| ---: | "
        "---: | ---: | ---: | ---: | ---: |\n");
    std::array<std::size_t, 3> classCount{};
    for (const IdPair& q : truth)
      classCount[2 - visible.count(q.first) - visible.count(q.second)]++;
    for (int layers : {1, 2, 3, 4}) {
      scene::CollisionDesc d = own;
      d.layers = layers;
      const CdtDetection det = detectCdt(d, camera, p, truth);
      const std::vector<IdPair> seen = collision::canonicalPairs(det.cdt->seenPairs());
      std::array<std::size_t, 3> found{};
      for (const IdPair& q : truth) {
        if (std::binary_search(seen.begin(), seen.end(), q))
          found[2 - visible.count(q.first) - visible.count(q.second)]++;
      }
      auto frac = [](std::size_t a, std::size_t b) {
        return b ? static_cast<double>(a) / static_cast<double>(b) : 0.0;
      };
      std::printf("| %d | %.3f | %.3f | %.3f | %.3f | %.1f |\n", layers,
                  frac(found[0], classCount[0]), frac(found[1], classCount[1]),
                  frac(found[2], classCount[2]), det.recall.pairRecall(), det.ms);
    }
    std::printf("\n(%zu / %zu / %zu true pairs in the three classes.)\n", classCount[0],
                classCount[1], classCount[2]);
  }

  // (4) Depth mismatch: near in 3D but far in texels (missed), near in texels but far in depth
  // (samples spent on nothing, or with curr_pos from the texel, false partners).
  std::printf("\n**4. Depth mismatch**\n\n");
  {
    std::map<std::uint32_t, std::size_t> indexOf;
    for (std::size_t i = 0; i < p.size(); ++i) indexOf[p.id[i]] = i;
    std::printf(
        "True pairs (both on the texture) by the texel distance between their base texels (r = 1\n"
        "reaches 1), and pair recall (r = 1) by the pair's distance from the view centre (NDC "
        "radius;\n"
        "the paper's groups 2 and 3), for the scene camera and a close-up (eq. 1 offset):\n\n");
    std::printf(
        "| camera | texels 0-1 | 2 | 3-4 | > 4 | recall, radius < 0.25 | 0.25-0.5 | 0.5-0.75 | >= "
        "0.75 |\n");
    std::printf("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for (double factor : {1.0, 0.4}) {
      scene::CollisionDesc d = own;
      d.camera = scene::CdtCameraMode::Offset;
      d.offset = static_cast<float>((factor - 1.0) * distance);
      const CdtDetection det = detectCdt(d, camera, p, truth);
      const cdt::View& view = det.cdt->settings().view;
      std::array<std::size_t, 4> byDistance{};  // texel distance 0-1, 2, 3-4, >4
      std::array<std::size_t, 4> byRadius{}, byRadiusFound{};
      const std::vector<IdPair> seen = collision::canonicalPairs(det.cdt->seenPairs());
      for (const IdPair& q : truth) {
        const std::size_t i = indexOf[q.first], j = indexOf[q.second];
        const cdt::TexelAddress a = cdt::texelOf(view, p.x[i], p.y[i], p.z[i]),
                                b = cdt::texelOf(view, p.x[j], p.y[j], p.z[j]);
        if (!a.onScreen || !b.onScreen) continue;
        const int t = std::max(std::abs(a.x - b.x), std::abs(a.y - b.y));
        byDistance[t <= 1 ? 0 : t == 2 ? 1 : t <= 4 ? 2 : 3]++;
        const double rx = (a.x + 0.5) / view.width * 2 - 1, ry = (a.y + 0.5) / view.height * 2 - 1;
        const double radius = std::sqrt(rx * rx + ry * ry);
        const int bucket = radius < 0.25 ? 0 : radius < 0.5 ? 1 : radius < 0.75 ? 2 : 3;
        byRadius[bucket]++;
        byRadiusFound[bucket] += std::binary_search(seen.begin(), seen.end(), q);
      }
      const double total =
          static_cast<double>(byDistance[0] + byDistance[1] + byDistance[2] + byDistance[3]);
      std::printf("| %.1f m | %.3f | %.3f | %.3f | %.3f |", factor * distance,
                  byDistance[0] / total, byDistance[1] / total, byDistance[2] / total,
                  byDistance[3] / total);
      for (int b = 0; b < 4; ++b) {
        if (byRadius[b] == 0)
          std::printf(" - |");
        else
          std::printf(" %.3f (%zu) |", static_cast<double>(byRadiusFound[b]) / byRadius[b],
                      byRadius[b]);
      }
      std::printf("\n");
    }
    std::printf("\n");
    const CdtDetection det = detectCdt(own, camera, p, truth);
    const cdt::View& view = det.cdt->settings().view;
    // Samples: occupied window texels whose particle is out of range (near in texels, far in
    // depth).
    std::size_t samples = 0, inRange = 0;
    for (const cdt::Diagnostics& dg : det.cdt->diagnostics()) inRange += dg.candidates;
    const auto& tex = det.cdt->texture();
    for (std::size_t i = 0; i < p.size(); ++i) {
      const cdt::TexelAddress a = cdt::texelOf(view, p.x[i], p.y[i], p.z[i]);
      if (!a.onScreen) continue;
      for (int ty = -1; ty <= 1; ++ty) {
        for (int tx = -1; tx <= 1; ++tx) {
          const int x = a.x + tx, y = a.y + ty;
          if (x < 0 || y < 0 || x >= tex.width || y >= tex.height) continue;
          const auto& t = tex.at(0, x, y);
          samples += t[3] >= 0 && static_cast<std::uint32_t>(t[3]) != p.id[i];
        }
      }
    }
    const CdtDetection paper = detectCdt(paperCdt(snap.scene), camera, p, truth);
    std::printf(
        "Of the occupied texels a particle samples (r = 1), %.1f%% hold a particle within range: "
        "%.1f%% are near\n"
        "in texels but farther in depth. With curr_pos from the base texel (the paper), %.1f%% of "
        "chosen partners\n"
        "are not within range of the particle itself and %zu seen pairs are false.\n",
        samples ? 100.0 * inRange / samples : 0.0,
        samples ? 100.0 - 100.0 * inRange / samples : 0.0,
        100.0 * (1.0 - paper.recall.partnerPrecision()), paper.recall.falsePairs);
  }
}

}  // namespace sph::collisionbench
