#pragma once
/// @file selectors.hpp  A `side` boundary selector in one call, for the boundary tests (2D and 3D).

#include <hemicontact/mesh/boundary.hpp>

#include <string>

namespace hemicontact::test {

/// @return a selector of side @p name (left, right, bottom, top; 3D also front, back) over
/// [@p from, @p to) with error context @p context.
inline BoundarySelector side(const std::string& name, const std::string& context, double from = -INF, double to = INF) {
  BoundarySelector s;
  s.side = name;
  s.context = context;
  s.from = from;
  s.to = to;
  return s;
}

}  // namespace hemicontact::test
