// Private to REnginePhysics: Cholesky factorisation of a symmetric positive definite matrix
// in skyline (envelope) storage. Row i keeps its columns first[i] .. i, packed at
// offset[i]; the factor has the same envelope, so a chain of joints (each couples only
// with its neighbours) costs O(m b^2) time and O(m b) memory for bandwidth b instead of
// O(m^3) and O(m^2).
#pragma once

#include <REngineMath/RMath.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace REngine::solver {

// L(i, k) for first[i] <= k <= i.
inline std::size_t SkylineAt(const std::uint32_t* first, const std::uint32_t* offset, int i, int k) {
  return offset[i] + static_cast<std::size_t>(k - static_cast<int>(first[i]));
}

// In place: M holds the lower envelope of the matrix, and on return its factor L (M = L L^T).
// False when the matrix is not positive definite.
inline bool SkylineCholesky(RScalar* M, int m, const std::uint32_t* first, const std::uint32_t* offset,
                            RScalar* inverseDiagonal) {
  for (int i = 0; i < m; ++i) {
    const int fi = static_cast<int>(first[i]);
    for (int j = fi; j <= i; ++j) {
      const int fj = static_cast<int>(first[j]);
      RScalar s = M[SkylineAt(first, offset, i, j)];
      const int k0 = std::max(fi, fj);
      const RScalar* Li = M + SkylineAt(first, offset, i, k0);
      const RScalar* Lj = M + SkylineAt(first, offset, j, k0);
      for (int k = 0; k < j - k0; ++k) s -= Li[k] * Lj[k];
      if (j < i) {
        M[SkylineAt(first, offset, i, j)] = s * inverseDiagonal[j];
      } else {
        if (!(s > 0)) return false;
        const RScalar d = std::sqrt(s);
        M[SkylineAt(first, offset, i, i)] = d;
        inverseDiagonal[i] = 1 / d;
      }
    }
  }
  return true;
}

// Solves L L^T x = x in place with the factor above.
inline void SkylineSolve(const RScalar* L, int m, const std::uint32_t* first, const std::uint32_t* offset,
                         const RScalar* inverseDiagonal, RScalar* x) {
  for (int i = 0; i < m; ++i) {
    const int fi = static_cast<int>(first[i]);
    const RScalar* Li = L + offset[i];
    RScalar s = x[i];
    for (int k = fi; k < i; ++k) s -= Li[k - fi] * x[k];
    x[i] = s * inverseDiagonal[i];
  }
  for (int i = m - 1; i >= 0; --i) {
    const int fi = static_cast<int>(first[i]);
    const RScalar* Li = L + offset[i];
    x[i] *= inverseDiagonal[i];
    for (int k = fi; k < i; ++k) x[k] -= Li[k - fi] * x[i];
  }
}

}  // namespace REngine::solver
