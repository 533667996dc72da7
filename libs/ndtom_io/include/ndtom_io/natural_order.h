// File names in the order people number them: full2 before full10.
#pragma once

#include <string>

namespace ndtom::io {

/// Compares runs of digits by value and everything else by character, so "full9.pcd" <
/// "full10.pcd"; equal values with different zero padding fall back to plain order.
bool naturalLess(const std::string& a, const std::string& b);

}  // namespace ndtom::io
