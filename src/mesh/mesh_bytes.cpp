// A Mesh as bytes and back (mesh/mesh_bytes.hpp): a tag, then every field with its counts first,
// read back with each count and index checked before it is used.
#include <hemicontact/mesh/mesh_bytes.hpp>

#include <hemicontact/core/error.hpp>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace hemicontact {
namespace {

constexpr char TAG[8] = {'h', 'c', 'm', 'e', 's', 'h', '0', '1'};

struct Writer {
  std::string out;
  template <class T>
  void put(const T& v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <class T>
  void put_array(const T* p, size_t n) {
    put(static_cast<std::int64_t>(n));
    out.append(reinterpret_cast<const char*>(p), n * sizeof(T));
  }
};

struct Reader {
  std::string_view in;
  size_t at = 0;
  [[noreturn]] static void bad(const std::string& why) { input_error("the mesh's bytes: " + why); }
  template <class T>
  T get() {
    if (in.size() - at < sizeof(T)) bad("they end early");
    T v;
    std::memcpy(&v, in.data() + at, sizeof v);
    at += sizeof v;
    return v;
  }
  // A count of T's, within what is left (so that no count can ask for more memory than was sent).
  size_t count(size_t item_bytes) {
    const auto n = get<std::int64_t>();
    if (n < 0 || static_cast<size_t>(n) > (in.size() - at) / item_bytes) bad("a count beyond their end");
    return static_cast<size_t>(n);
  }
  template <class T>
  std::vector<T> get_array() {
    std::vector<T> v(count(sizeof(T)));
    if (!v.empty()) std::memcpy(v.data(), in.data() + at, v.size() * sizeof(T));
    at += v.size() * sizeof(T);
    return v;
  }
};

void check_indices(const IMat& m, Index below, const char* what) {
  for (Index i = 0; i < m.size(); ++i)
    if (m.data()[i] < 0 || m.data()[i] >= below) Reader::bad(std::string("a ") + what + " names a node out of range");
}

}  // namespace

std::string mesh_to_bytes(const Mesh& m) {
  Writer w;
  w.out.append(TAG, sizeof TAG);
  w.put(static_cast<std::int32_t>(m.dim));
  w.put_array(m.points.data(), static_cast<size_t>(m.points.size()));
  w.put_array(m.cells.data(), static_cast<size_t>(m.cells.size()));
  w.put_array(m.facets.data(), static_cast<size_t>(m.facets.size()));
  std::vector<std::int32_t> parts;
  for (Part p : m.facet_part) parts.push_back(static_cast<std::int32_t>(p));
  w.put_array(parts.data(), parts.size());
  w.put_array(m.facet_load.data(), m.facet_load.size());
  w.put(static_cast<std::int64_t>(m.tractions.size()));
  for (const Vec& t : m.tractions) w.put_array(t.data(), static_cast<size_t>(t.size()));
  w.put(static_cast<std::int64_t>(m.facet_groups.size()));
  for (const auto& [name, facets] : m.facet_groups) {
    w.put_array(name.data(), name.size());
    w.put_array(facets.data(), facets.size());
  }
  w.put_array(m.node_fixed.data(), m.node_fixed.size());
  w.put_array(m.origin.data(), m.origin.size());
  return std::move(w.out);
}

Mesh mesh_from_bytes(std::string_view bytes) {
  Reader r{bytes};
  if (bytes.size() < sizeof TAG || std::memcmp(bytes.data(), TAG, sizeof TAG) != 0) Reader::bad("not a mesh's");
  r.at = sizeof TAG;
  Mesh m;
  m.dim = r.get<std::int32_t>();
  if (m.dim != 2 && m.dim != 3) Reader::bad("dimension " + std::to_string(m.dim));
  const auto matrix = [&](auto& M, int cols, const char* what) {
    using T = typename std::decay_t<decltype(M)>::Scalar;
    const std::vector<T> v = r.template get_array<T>();
    if (v.size() % static_cast<size_t>(cols) != 0) Reader::bad(std::string(what) + " not in rows of " + std::to_string(cols));
    M.resize(static_cast<Index>(v.size() / static_cast<size_t>(cols)), cols);
    if (!v.empty()) std::memcpy(M.data(), v.data(), v.size() * sizeof(T));
  };
  matrix(m.points, m.dim, "points");
  matrix(m.cells, m.dim + 1, "cells");
  matrix(m.facets, m.dim, "facets");
  check_indices(m.cells, m.num_nodes(), "cell");
  check_indices(m.facets, m.num_nodes(), "facet");
  for (const std::int32_t p : r.get_array<std::int32_t>()) {
    if (p < 0 || p > 3) Reader::bad("an unknown boundary part " + std::to_string(p));
    m.facet_part.push_back(static_cast<Part>(p));
  }
  m.facet_load = r.get_array<int>();
  m.tractions.resize(r.count(sizeof(std::int64_t)));
  for (Vec& t : m.tractions) {
    const std::vector<double> v = r.get_array<double>();
    t = Eigen::Map<const Vec>(v.data(), static_cast<Index>(v.size()));
  }
  for (size_t g = r.count(2 * sizeof(std::int64_t)); g > 0; --g) {
    const std::vector<char> name = r.get_array<char>();
    std::vector<Index> facets = r.get_array<Index>();
    for (const Index f : facets)
      if (f < 0 || f >= m.num_facets()) Reader::bad("a facet group names a facet out of range");
    m.facet_groups[std::string(name.begin(), name.end())] = std::move(facets);
  }
  m.node_fixed = r.get_array<unsigned char>();
  const std::vector<char> origin = r.get_array<char>();
  m.origin.assign(origin.begin(), origin.end());
  const auto F = static_cast<size_t>(m.num_facets());
  if (m.facet_part.size() != F || (!m.facet_load.empty() && m.facet_load.size() != F) ||
      (!m.node_fixed.empty() && m.node_fixed.size() != static_cast<size_t>(m.num_nodes())))
    Reader::bad("a per-facet or per-node list of another length");
  for (const int l : m.facet_load)
    if (l < -1 || l >= static_cast<int>(m.tractions.size())) Reader::bad("a facet's load out of range");
  if (r.at != bytes.size()) Reader::bad("more bytes than a mesh's");
  return m;
}

}  // namespace hemicontact
