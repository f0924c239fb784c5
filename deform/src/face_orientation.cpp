#include "sculpt/deform/face_orientation.hpp"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace sculpt::deform {
namespace {

// One directed use of an undirected edge by a triangle.
struct EdgeUse {
  std::uint64_t key;  // the smaller vertex index in the high half, the larger in the low half
  std::uint32_t face;
  bool forward;  // the triangle runs the edge from the smaller index to the larger
};

struct Neighbour {
  std::uint32_t face;
  bool same_direction;  // both run the shared edge the same way: one of them must turn
};

}  // namespace

FaceOrientation orient_faces(PointModel& model) {
  std::vector<std::uint32_t>& tri = model.triangles;
  if (tri.size() % 3 != 0) {
    throw std::invalid_argument("orient_faces: triangle index count " + std::to_string(tri.size()) +
                                " is not a multiple of 3");
  }
  const std::size_t faces = tri.size() / 3;
  for (std::size_t i = 0; i < tri.size(); ++i) {
    if (tri[i] >= model.size()) {
      throw std::invalid_argument("orient_faces: triangle " + std::to_string(i / 3) + " refers to point " +
                                  std::to_string(tri[i]) + " of " + std::to_string(model.size()));
    }
  }
  FaceOrientation result;
  if (faces == 0) return result;

  std::vector<EdgeUse> uses;
  uses.reserve(3 * faces);
  for (std::uint32_t f = 0; f < faces; ++f) {
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = tri[3 * f + e], b = tri[3 * f + (e + 1) % 3];
      if (a == b) continue;  // a degenerate triangle's collapsed edge joins nothing
      const std::uint32_t lo = std::min(a, b), hi = std::max(a, b);
      uses.push_back({(std::uint64_t{lo} << 32) | hi, f, a == lo});
    }
  }
  std::sort(uses.begin(), uses.end(),
            [](const EdgeUse& x, const EdgeUse& y) { return x.key != y.key ? x.key < y.key : x.face < y.face; });

  // Adjacency across manifold edges only (exactly two triangles), in compressed rows.
  std::vector<std::pair<std::uint32_t, Neighbour>> links;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    if (j - i == 2) {
      const bool same = uses[i].forward == uses[i + 1].forward;
      links.push_back({uses[i].face, {uses[i + 1].face, same}});
      links.push_back({uses[i + 1].face, {uses[i].face, same}});
    } else if (j - i > 2) {
      ++result.conflicts;
    }
    i = j;
  }
  std::sort(links.begin(), links.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<std::size_t> row(faces + 1, 0);
  for (const auto& l : links) ++row[l.first + 1];
  for (std::size_t f = 0; f < faces; ++f) row[f + 1] += row[f];

  // Breadth-first over each piece: a neighbour across an edge both run the same way takes the
  // opposite flip. A neighbour already settled the other way stays as it is (counted below).
  std::vector<std::int8_t> flip(faces, -1);  // -1 unvisited, 0 keep, 1 turn
  std::vector<std::uint32_t> queue, piece;
  queue.reserve(faces);
  for (std::uint32_t seed = 0; seed < faces; ++seed) {
    if (flip[seed] >= 0) continue;
    ++result.components;
    piece.clear();
    queue.assign(1, seed);
    flip[seed] = 0;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::uint32_t f = queue[q];
      piece.push_back(f);
      for (std::size_t k = row[f]; k < row[f + 1]; ++k) {
        const Neighbour& n = links[k].second;
        const std::int8_t wanted = static_cast<std::int8_t>(flip[f] ^ (n.same_direction ? 1 : 0));
        if (flip[n.face] < 0) {
          flip[n.face] = wanted;
          queue.push_back(n.face);
        }
      }
    }
    // Which of the piece's two consistent windings: the one most of its faces already have.
    // The file's intent is respected (a hollow shell's cavity wall faces into the cavity, which
    // no rule from the geometry alone could tell from an inside-out surface); only the faces
    // that disagree with their neighbours turn.
    std::size_t turning = 0;
    for (std::uint32_t f : piece) turning += flip[f] == 1;
    if (2 * turning > piece.size()) {
      for (std::uint32_t f : piece) flip[f] ^= 1;
    }
  }
  for (const auto& [face, n] : links) {
    if (face < n.face && (flip[face] ^ flip[n.face]) != (n.same_direction ? 1 : 0)) ++result.conflicts;
  }

  for (std::size_t f = 0; f < faces; ++f) {
    if (!flip[f]) continue;
    std::swap(tri[3 * f + 1], tri[3 * f + 2]);
    ++result.turned;
  }
  return result;
}

}  // namespace sculpt::deform
