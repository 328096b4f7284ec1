#pragma once
// Is the container wide enough for the coarse particles? Hu et al. 2022 (appendix, after refs [54, 55]):
// bulk flow of scaled-up particles is free of boundary effects only while the container is at least 40
// particle diameters across (D/d >= 40); beyond that the velocity distribution shifts and broadens. A
// coarse-grained run that violates it still runs, with a warning that names the narrowest width.
#include <string>
#include <vector>
#include "core/scene.hpp"

namespace cgdem {

// One line per coarse-grained group (factor > 1) whose largest coarse diameter fits fewer than
// `min_ratio` times across the narrowest width among: periodic axes, cylinder walls (diameter) and pairs
// of facing parallel plane walls, leaving out widths along gravity (a bed's height is not a container
// width). Empty when every group has room, or no width is bounded.
std::vector<std::string> resolution_warnings(const Scene& scene, double min_ratio = 40);

} // namespace cgdem
