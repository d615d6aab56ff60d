// Two boxes proven apart by their separating axes (see RBoxPair.h).
#include "collision/RBoxPair.h"

#include <cmath>

namespace REngine {

bool BoxesApart(const RVec3& ha, const RVec3& hb, const RRelativePose& X, RScalar cutoff, RScalar& bound,
                RVec3& axis) {
  const RMat3& R = X.R_AB;  // column j: B's axis j in A's frame
  const RVec3& t = X.t_AB;
  // The bounds below hold for a rotation; a pose given through the API that is not one
  // (a scaled or sheared matrix) gets GJK's answer for what it describes instead.
  if (!((R.transpose() * R - RMat3::Identity()).cwiseAbs().maxCoeff() <= 1e-9)) return false;
  RMat3 absR;
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 3; ++j) absR(k, j) = std::abs(R(k, j));
  }
  // Each bound is computed to a few units in the last place of |t| + sizes; the proof asks
  // for more than that above the cutoff (the cutoff sits above the narrow phase's margin by
  // far more again, so a pair proven here is one GJK would also have left out).
  const RScalar slack = 1e-12 * (t.cwiseAbs().sum() + ha.sum() + hb.sum());
  const RScalar need = cutoff + slack;
  for (int k = 0; k < 3; ++k) {  // A's faces
    const RScalar s = std::abs(t[k]) - (ha[k] + hb[0] * absR(k, 0) + hb[1] * absR(k, 1) + hb[2] * absR(k, 2));
    if (s > need) {
      bound = s, axis = RVec3::Unit(k) * (t[k] >= 0 ? 1 : -1);
      return true;
    }
  }
  const RVec3 tB = R.transpose() * t;  // t in B's frame
  for (int j = 0; j < 3; ++j) {  // B's faces
    const RScalar s = std::abs(tB[j]) - (hb[j] + ha[0] * absR(0, j) + ha[1] * absR(1, j) + ha[2] * absR(2, j));
    if (s > need) {
      bound = s, axis = R.col(j) * (tB[j] >= 0 ? 1 : -1);
      return true;
    }
  }
  for (int k = 0; k < 3; ++k) {  // edge of A along k, edge of B along j
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      // |e_k x R_j|^2 = 1 - R_kj^2; nearly parallel edges have no axis of their own worth
      // the division (the face normals above cover them).
      const RScalar length2 = R(k1, j) * R(k1, j) + R(k2, j) * R(k2, j);
      if (length2 < 1e-6) continue;
      const RScalar along = t[k2] * R(k1, j) - t[k1] * R(k2, j);
      const RScalar rA = ha[k1] * absR(k2, j) + ha[k2] * absR(k1, j);
      const RScalar rB = hb[j1] * absR(k, j2) + hb[j2] * absR(k, j1);
      // (|along| - rA - rB) / length > need, without the root unless it holds (need > 0).
      const RScalar gap = std::abs(along) - rA - rB - slack;
      if (gap > 0 && gap * gap > need * need * length2) {
        const RScalar length = std::sqrt(length2);
        bound = (std::abs(along) - rA - rB) / length;
        RVec3 cross = RVec3::Zero();
        cross[k1] = -R(k2, j), cross[k2] = R(k1, j);  // e_k x R_j
        axis = cross / length * (along >= 0 ? 1 : -1);
        return true;
      }
    }
  }
  return false;
}

}  // namespace REngine
