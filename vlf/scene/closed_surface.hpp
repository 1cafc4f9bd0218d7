// closed_surface.hpp — is a set of polygons the boundary of a solid? A dielectric object
// must be (issue 14: light refracted into it must meet its far side from inside, and an
// open one would let it out through the hole unrefracted).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "vlf/scene/primitives.hpp"

namespace vlf {

// Vertices within `tol` of each other are one point. The surface is closed and consistently
// oriented when every directed edge a -> b of a polygon is matched by exactly one edge
// b -> a of another polygon, and by no second a -> b; it faces outward when the volume it
// encloses, signed by its winding, is positive. Returns nothing when all three hold, else a
// one-line description of the first offending edge (its end points in the polygons' frame)
// or of the inward winding.
std::optional<std::string> open_edge(const std::vector<Polygon>& polygons, double tol);

}  // namespace vlf
