// What CacheReader reads to continue a run: a frame's resume record (Restart#N: the run's state
// and what the frame's fields lack of the particles) and the rain feed's ledger alone.
#include "io/cache/CacheReader.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sph::io::cache {

rain::FeedState CacheReader::readRainFeed(std::size_t frame) const {
  checkFrame(frame);
  rain::FeedState f;
  const std::string group = "/" + cache::restartName(frame);
  if (!summary_.frames[frame].hasRestart) return f;
  try {
    h5::Handle g = h5::openCheckedGroup(file_.get(), group);
    if (!h5::hasAttribute(g.get(), "rain_landed_drops")) return f;
    f.landedDrops = h5::readUintAttribute(g.get(), "rain_landed_drops");
    f.particles = h5::readUintAttribute(g.get(), "rain_particles");
    f.pending = h5::readDoubleAttribute(g.get(), "rain_pending_volume");
  } catch (const h5::Error& e) {
    fail(group + ": " + e.what());
  }
  return f;
}

std::pair<run::RunState, Particles> CacheReader::readRestart(std::size_t frame,
                                                             const h5::Runs* runs) const {
  checkFrame(frame);
  const std::string group = "/" + cache::restartName(frame);
  if (!summary_.frames[frame].hasRestart) {
    fail("frame " + std::to_string(frame) + " has no resume record (" + group +
         (summary_.restart ? ")" : "): the run was written with output.restart = false"));
  }
  // Every field the frame holds, then what the resume record adds.
  Particles p = readFrame(frame, summary_.fields, runs);
  const std::size_t n = summary_.frames[frame].particles;
  std::size_t selected = n;  // the particles read
  if (runs) {
    selected = 0;
    for (const auto& run : *runs) selected += run.second;
  }
  run::RunState s;
  std::string item = "attributes";
  try {
    h5::Handle g = h5::openCheckedGroup(file_.get(), group);
    const hid_t r = g.get();
    s.time = h5::readDoubleAttribute(r, item = "time");
    s.step = h5::readUintAttribute(r, item = "step");
    s.lastDt = h5::readFloatAttribute(r, item = "last_dt");
    s.maxSpeed = h5::readFloatAttribute(r, item = "max_speed");
    s.maxAcceleration = h5::readFloatAttribute(r, item = "max_acceleration");
    s.nextId = static_cast<std::uint32_t>(h5::readUintAttribute(r, item = "next_id"));
    // Caches from before particles could be lost have no count: none were.
    if (h5::hasAttribute(r, "lost_particles"))
      s.lostParticles = h5::readUintAttribute(r, item = "lost_particles");
    if (h5::hasAttribute(r, "rain_landed_drops")) {
      s.rain.landedDrops = h5::readUintAttribute(r, item = "rain_landed_drops");
      s.rain.particles = h5::readUintAttribute(r, item = "rain_particles");
      s.rain.pending = h5::readDoubleAttribute(r, item = "rain_pending_volume");
    }
    const std::vector<double> travelled =
        h5::readDoubleArrayAttribute(r, item = "emitter_travelled");
    const std::vector<std::uint64_t> emitted =
        h5::readUintArrayAttribute(r, item = "emitter_emitted");
    const std::vector<std::uint64_t> started =
        h5::readUintArrayAttribute(r, item = "emitter_started");
    if (emitted.size() != travelled.size() || started.size() != travelled.size()) {
      fail(group + ": the emitter attributes disagree in length");
    }
    for (std::size_t e = 0; e < travelled.size(); ++e)
      s.emitters.push_back({travelled[e], emitted[e], started[e] != 0});
    for (std::size_t f = 0; f < cache::kFieldCount; ++f) {
      const auto field = static_cast<cache::Field>(f);
      if (!cache::restartFields()[f] || summary_.fields[f]) continue;
      item = cache::fieldName(field);
      if (!h5::hasLink(r, item) && field != cache::Field::Id &&
          h5::hasAttribute(r, item + "_constant")) {
        (p.*cache::floatMember(field))
            .assign(selected, h5::readFloatAttribute(r, item + "_constant"));
        continue;
      }
      if (!h5::hasLink(r, item))
        fail("resume record " + group + " has no dataset " + group + "/" + item);
      if (h5::datasetLength(r, item) != n) {
        fail("dataset " + group + "/" + item + " does not have the frame's " + std::to_string(n) +
             " values");
      }
      if (field == cache::Field::Id)
        p.id = h5::readDataset<std::uint32_t>(r, item, runs);
      else
        p.*cache::floatMember(field) = h5::readDataset<float>(r, item, runs);
    }
    // The pressure solver's per-particle state, what the run had of it.
    const std::pair<const char*, std::vector<float>*> warm[] = {
        {cache::kWarmDensityName, &s.warmStart.density},
        {cache::kWarmDivergenceName, &s.warmStart.divergence},
        {cache::kWallShareName, &s.warmStart.wallShare}};
    for (const auto& [name, values] : warm) {
      item = name;
      if (!h5::hasLink(r, item)) continue;
      if (h5::datasetLength(r, item) != n) {
        fail("dataset " + group + "/" + item + " does not have the frame's " + std::to_string(n) +
             " values");
      }
      *values = h5::readDataset<float>(r, item, runs);
    }
  } catch (const h5::Error& e) {
    fail("cannot read " + item + " of the resume record " + group + " (" + e.what() + ")");
  }
  // What neither holds is recomputed by the next step before it is read.
  p.forEachField([selected](auto& field) { field.resize(selected); });
  return {s, p};
}

}  // namespace sph::io::cache
