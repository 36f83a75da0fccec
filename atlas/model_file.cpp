#include "atlas/model_file.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/error.h"

namespace isoatlas::atlas {
namespace {

constexpr char kMagic[8] = {'I', 'S', 'O', 'A', 'T', 'L', 'A', 'S'};
constexpr std::uint32_t kVersion = 1;

class Writer {
public:
  template <class T>
  void put(const T& value) {
    const char* p = reinterpret_cast<const char*>(&value);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  void putVec(const Vec3& v) { put(v.x), put(v.y), put(v.z); }
  std::string bytes;
};

void section(std::ofstream& out, const char tag[4], const Writer& w) {
  out.write(tag, 4);
  const std::uint64_t size = w.bytes.size();
  out.write(reinterpret_cast<const char*>(&size), sizeof size);
  out.write(w.bytes.data(), std::streamsize(w.bytes.size()));
}

class Reader {
public:
  Reader(const std::string& path, const std::string& bytes, std::size_t begin, std::size_t end)
      : path_(path), bytes_(bytes), at_(begin), end_(end) {}
  template <class T>
  T get() {
    need(sizeof(T));
    T value;
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  // A count of items of `itemBytes` each that must fit in what is left of the section.
  std::uint64_t count(std::size_t itemBytes, const char* what) {
    const std::uint64_t n = get<std::uint64_t>();
    if (n > (end_ - at_) / itemBytes) fail(std::string(what) + " count " + std::to_string(n) + " exceeds the section");
    return n;
  }
  double finite() {
    const double v = get<double>();
    if (!std::isfinite(v)) fail("a coordinate is not finite");
    return v;
  }
  Vec3 vec() {
    Vec3 v;
    v.x = finite(), v.y = finite(), v.z = finite();
    return v;
  }
  std::uint32_t index(std::uint64_t limit, const char* what) {
    const std::uint32_t i = get<std::uint32_t>();
    if (i >= limit) fail(std::string(what) + " index " + std::to_string(i) + " out of range");
    return i;
  }
  [[noreturn]] void fail(const std::string& why) const {
    throw Error(path_ + ": byte " + std::to_string(at_) + ": " + why);
  }
  void need(std::size_t n) const {
    if (n > end_ - at_) fail("the section ends early");
  }
  bool done() const { return at_ == end_; }

private:
  const std::string& path_;
  const std::string& bytes_;
  std::size_t at_, end_;
};

}  // namespace

void writeModel(const std::string& path, const Model& model) {
  // Checked before the file is touched, so a refused model loses nothing already there.
  require(model.dense.allFacesHave(3), path + ": the dense mesh must be triangles");
  require(multires::isChartSize(model.chartSize), path + ": chart size " + std::to_string(model.chartSize) +
                                                      " is not 2^k + 1 between 3 and " +
                                                      std::to_string(multires::kMaxChartSize));
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw Error(path + ": cannot open for writing");
  out.write(kMagic, 8);
  out.write(reinterpret_cast<const char*>(&kVersion), 4);

  Writer head;
  head.put(model.chartSize);
  section(out, "HEAD", head);

  Writer dense;
  dense.put(std::uint64_t(model.dense.vertexCount()));
  for (const Vec3& p : model.dense.positions) dense.putVec(p);
  dense.put(std::uint64_t(model.dense.faceCount()));
  for (const std::uint32_t c : model.dense.faceVertices) dense.put(c);
  section(out, "DENS", dense);

  const multires::BaseMesh& b = model.base;
  Writer base;
  base.put(std::uint64_t(b.vertexCount()));
  for (std::size_t i = 0; i < b.vertexCount(); ++i) base.putVec(b.positions[i]), base.put(b.denseVertex[i]);
  base.put(std::uint64_t(b.triangleCount()));
  for (const auto& t : b.triangles) base.put(t[0]), base.put(t[1]), base.put(t[2]);
  base.put(std::uint64_t(b.tiles.size()));
  for (const auto& t : b.tiles) base.put(t[0]), base.put(t[1]);
  base.put(std::uint64_t(b.denseTriangle.size()));
  for (std::size_t i = 0; i < b.denseTriangle.size(); ++i) {
    base.put(b.denseTriangle[i]);
    for (const double w : b.denseBary[i]) base.put(w);
  }
  section(out, "BASE", base);
  if (!out.flush()) throw Error(path + ": write failed (disk full?)", ErrorKind::Failure);
}

Model readModel(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open (missing or unreadable)");
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (bytes.size() < 12 || std::memcmp(bytes.data(), kMagic, 8) != 0) throw Error(path + ": not an isoatlas model file");
  std::uint32_t version;
  std::memcpy(&version, bytes.data() + 8, 4);
  if (version != kVersion)
    throw Error(path + ": model format version " + std::to_string(version) + " (this isoatlas reads " +
                std::to_string(kVersion) + ")");
  Model model;
  bool head = false, dense = false, base = false;
  std::size_t at = 12;
  while (at < bytes.size()) {
    if (bytes.size() - at < 12) throw Error(path + ": byte " + std::to_string(at) + ": truncated section header");
    const std::string tag = bytes.substr(at, 4);
    std::uint64_t size;
    std::memcpy(&size, bytes.data() + at + 4, 8);
    at += 12;
    if (size > bytes.size() - at)
      throw Error(path + ": byte " + std::to_string(at) + ": section " + tag + " runs past the end of the file");
    Reader r(path, bytes, at, at + size);
    bool& seen = tag == "HEAD" ? head : tag == "DENS" ? dense : base;
    const bool known = tag == "HEAD" || tag == "DENS" || tag == "BASE";
    if (known && seen) r.fail("a second " + tag + " section");  // would mix two models' counts
    if (tag == "HEAD") {
      model.chartSize = r.get<std::uint32_t>();
      if (!multires::isChartSize(model.chartSize)) r.fail("chart size " + std::to_string(model.chartSize));
      head = true;
    } else if (tag == "DENS") {
      Mesh& m = model.dense;
      const std::uint64_t nv = r.count(24, "vertex");
      m.positions.resize(nv);
      for (auto& p : m.positions) p = r.vec();
      const std::uint64_t nt = r.count(12, "triangle");
      for (std::uint64_t t = 0; t < nt; ++t) {
        const std::uint32_t a = r.index(nv, "vertex"), b = r.index(nv, "vertex"), c = r.index(nv, "vertex");
        m.addFace({a, b, c});
      }
      dense = true;
    } else if (tag == "BASE") {
      multires::BaseMesh& b = model.base;
      const std::uint64_t nv = r.count(32, "base vertex");
      for (std::uint64_t i = 0; i < nv; ++i) {
        b.positions.push_back(r.vec());
        const std::int64_t d = r.get<std::int64_t>();
        if (d < -1) r.fail("dense vertex " + std::to_string(d));
        b.denseVertex.push_back(d);
      }
      const std::uint64_t nt = r.count(12, "base triangle");
      for (std::uint64_t t = 0; t < nt; ++t)
        b.triangles.push_back({r.index(nv, "base vertex"), r.index(nv, "base vertex"), r.index(nv, "base vertex")});
      const std::uint64_t tiles = r.count(8, "tile");
      for (std::uint64_t t = 0; t < tiles; ++t) b.tiles.push_back({r.index(nt, "tile triangle"), r.index(nt, "tile triangle")});
      const std::uint64_t nd = r.count(28, "parametrised vertex");
      for (std::uint64_t i = 0; i < nd; ++i) {
        b.denseTriangle.push_back(r.index(nt, "base triangle"));
        std::array<double, 3> w{r.finite(), r.finite(), r.finite()};
        b.denseBary.push_back(w);
      }
      base = true;
    }
    if (known && !r.done()) r.fail("section " + tag + " has trailing bytes");
    at += size;
  }
  if (!head || !dense || !base) throw Error(path + ": the model lacks a HEAD, DENS or BASE section");
  if (model.base.denseTriangle.size() != model.dense.vertexCount())
    throw Error(path + ": the parametrisation covers " + std::to_string(model.base.denseTriangle.size()) +
                " vertices, the dense mesh has " + std::to_string(model.dense.vertexCount()));
  for (const std::int64_t d : model.base.denseVertex)
    if (d >= std::int64_t(model.dense.vertexCount())) throw Error(path + ": a base vertex names a missing dense vertex");
  return model;
}

}  // namespace isoatlas::atlas
