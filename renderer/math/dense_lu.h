#pragma once
// Solving a small dense linear system A X = B by LU decomposition with partial pivoting,
// for the manifold walk's constraint Jacobian (at most 14 x 14).
#include <vector>

namespace pathfarm {

// A (n x n) and B (n x columns) are row-major and overwritten: on success B holds X.
// False when A is singular to working precision: a pivot below 1e-12 times A's largest
// entry, or anything not finite.
bool solveDense(std::vector<double>& a, int n, std::vector<double>& b, int columns);

}  // namespace pathfarm
