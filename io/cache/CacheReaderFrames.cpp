// What CacheReader reads of a frame: its particles (any set of fields, or a rank's runs of
// them), the boundary and a rendered picture, each after the frame is checked to be one the
// summary holds. The resume record is read in CacheReaderResume.cpp.
#include "io/cache/CacheReader.h"

#include <algorithm>
#include <string>
#include <vector>

namespace sph::io::cache {
namespace {

using h5::checked;

std::string frameRange(std::size_t frames) {
  if (frames == 0) return "the cache has no complete frame";
  return "the cache has frames 0-" + std::to_string(frames - 1);
}

}  // namespace

std::vector<std::string> sceneEdits(const CacheSummary& summary) {
  std::vector<std::string> edits;
  const std::string& text = summary.sceneOverrides;
  for (std::size_t from = 0; from < text.size();) {
    const std::size_t end = std::min(text.find('\n', from), text.size());
    if (end > from) edits.push_back(text.substr(from, end - from));
    from = end + 1;
  }
  return edits;
}

std::string describeFrames(const std::vector<std::size_t>& frames) {
  const std::size_t n = frames.size();
  if (n == 0) return "no frame";
  std::string text = std::to_string(n) + (n == 1 ? " frame (" : " frames (");
  const std::size_t stride = n > 1 ? frames[1] - frames[0] : 1;
  bool evenlySpaced = n > 2 && stride > 0;
  for (std::size_t i = 1; i < n && evenlySpaced; ++i)
    evenlySpaced = frames[i] - frames[i - 1] == stride;
  if (n == 1) {
    text += std::to_string(frames[0]);
  } else if (evenlySpaced) {
    text += std::to_string(frames.front()) + "-" + std::to_string(frames.back());
    if (stride > 1) text += ", every " + std::to_string(stride) + " frames";
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      if (i == 8 && n > 9) {
        text += ", ... " + std::to_string(frames.back());
        break;
      }
      text += (i ? ", " : "") + std::to_string(frames[i]);
    }
  }
  return text + ")";
}

void CacheReader::checkFrame(std::size_t frame) const {
  if (frame < summary_.frames.size()) return;
  fail("frame " + std::to_string(frame) +
       " is out of range: " + frameRange(summary_.frames.size()));
}

Particles CacheReader::readFrame(std::size_t frame, const cache::FieldSet& fields,
                                 const h5::Runs* runs) const {
  checkFrame(frame);
  const std::string group = "/" + cache::stepName(frame);
  Particles p;
  std::string dataset;
  try {
    h5::Handle g = h5::openCheckedGroup(file_.get(), group);
    const std::size_t n = summary_.frames[frame].particles;
    for (std::size_t f = 0; f < cache::kFieldCount; ++f) {
      if (!fields[f]) continue;
      const auto field = static_cast<cache::Field>(f);
      dataset = cache::fieldName(field);
      if (!h5::hasLink(g.get(), dataset)) {
        fail("frame " + std::to_string(frame) + " has no dataset " + group + "/" + dataset +
             " (it holds " + cache::describeFields(summary_.fields) + ")");
      }
      const std::size_t length = h5::datasetLength(g.get(), dataset);
      if (length != n) {
        fail("dataset " + group + "/" + dataset + " has " + std::to_string(length) +
             " values but " + group + "/x has " + std::to_string(n));
      }
      if (field == cache::Field::Id)
        p.id = h5::readDataset<std::uint32_t>(g.get(), dataset, runs);
      else
        p.*cache::floatMember(field) = h5::readDataset<float>(g.get(), dataset, runs);
    }
  } catch (const h5::Error& e) {
    fail("cannot read dataset " + group + "/" + dataset + " (" + e.what() + ")");
  }
  return p;
}

std::vector<std::vector<float>> CacheReader::readBoundary() const {
  std::vector<std::vector<float>> xyz(3);
  if (h5::objectType(file_.get(), cache::kBoundaryGroup) != H5O_TYPE_GROUP)
    fail("has no /Boundary group");
  const char* names[3] = {"x", "y", "z"};
  try {
    h5::Handle b =
        h5::openCheckedGroup(file_.get(), cache::kBoundaryGroup);
    for (int a = 0; a < 3; ++a) xyz[a] = h5::readDataset<float>(b.get(), names[a]);
  } catch (const h5::Error& e) {
    fail(std::string("cannot read /Boundary (") + e.what() + ")");
  }
  return xyz;
}

RenderedFrame CacheReader::readRenderedFrame(const std::string& renderer, std::size_t frame) const {
  const std::vector<std::size_t>* frames = nullptr;
  for (const auto& [name, held] : summary_.renderers) {
    if (name == renderer) frames = &held;
  }
  if (!frames) fail("has no rendered frames of renderer '" + renderer + "'");
  if (!std::binary_search(frames->begin(), frames->end(), frame)) {
    fail("has no picture of frame " + std::to_string(frame) + " from renderer '" + renderer +
         "' (it has " + describeFrames(*frames) + ")");
  }
  std::string path = "/" + cache::renderedFrameName(renderer, frame);
  if (!h5::hasLink(file_.get(), path.substr(1))) {
    path = std::string("/") + cache::kLegacyRenderGroup + "/" + renderer + "/" +
           cache::legacyRenderedFrameName(frame);
  }
  RenderedFrame out;
  try {
    h5::Handle set = h5::openCheckedDataset(file_.get(), path);
    h5::Handle space = checked(H5Dget_space(set.get()), "read its shape");
    hsize_t dims[3] = {0, 0, 0};
    if (H5Sget_simple_extent_ndims(space.get()) != 3)
      fail("dataset " + path + " is not height x width x 3");
    H5Sget_simple_extent_dims(space.get(), dims, nullptr);
    if (dims[2] != 3) fail("dataset " + path + " is not height x width x 3");
    out.height = static_cast<int>(dims[0]);
    out.width = static_cast<int>(dims[1]);
    out.rgb.resize(dims[0] * dims[1] * 3);
    h5::check(H5Dread(set.get(), H5T_NATIVE_UINT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.rgb.data()),
              "read " + path);
    out.time = h5::readDoubleAttribute(set.get(), cache::kTimeAttr);
  } catch (const h5::Error& e) {
    fail("cannot read " + path + " (" + e.what() + ")");
  }
  return out;
}

}  // namespace sph::io::cache
