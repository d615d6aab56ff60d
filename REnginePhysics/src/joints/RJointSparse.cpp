// RJointSparse (RJointSparse.h): the saddle-point system of a large joint island, ordered
// by approximate minimum degree and factored by Eigen's simplicial LDL^T.
#include "joints/RJointSparse.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>

namespace REngine::joints {

struct RJointSparse::RImpl {
  using Matrix = Eigen::SparseMatrix<RScalar, Eigen::ColMajor, int>;
  // The system permuted (its upper triangle), the factor of it in natural order: the
  // ordering is applied here, once per pattern, so that a refactor copies nothing.
  Matrix a;
  Eigen::SimplicialLDLT<Matrix, Eigen::Upper, Eigen::NaturalOrdering<int>> ldlt;
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;  // unknown -> its place
  std::vector<int> patternR, patternC;  // the entries' pattern the ordering was made for
  std::vector<int> slot;                // entry -> its index in a's values
  Eigen::Matrix<RScalar, Eigen::Dynamic, 1> z, y;
  bool analysed = false;
};

RJointSparse::RJointSparse() : m_impl(std::make_unique<RImpl>()) {}
RJointSparse::~RJointSparse() = default;

void RJointSparse::Begin(int size) {
  m_size = size;
  m_r.clear(), m_c.clear(), m_v.clear();
}

bool RJointSparse::Factor() {
  RImpl& s = *m_impl;
  for (RScalar v : m_v) {
    if (!std::isfinite(v)) return false;
  }
  const bool samePattern = s.analysed && s.a.rows() == m_size && s.patternR == m_r && s.patternC == m_c;
  if (!samePattern) {
    // The pattern's ordering: minimum degree on the symmetric pattern.
    std::vector<Eigen::Triplet<RScalar, int>> entries;
    entries.reserve(m_r.size());
    for (std::size_t k = 0; k < m_r.size(); ++k) {
      entries.emplace_back(std::min(m_r[k], m_c[k]), std::max(m_r[k], m_c[k]), RScalar(1));
    }
    RImpl::Matrix pattern(m_size, m_size);
    pattern.setFromTriplets(entries.begin(), entries.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse;
    Eigen::AMDOrdering<int> amd;
    amd(pattern.selfadjointView<Eigen::Upper>(), inverse);
    s.order = inverse.inverse();
    const int* place = s.order.indices().data();
    entries.clear();
    for (std::size_t k = 0; k < m_r.size(); ++k) {
      const int r = place[m_r[k]], c = place[m_c[k]];
      entries.emplace_back(std::min(r, c), std::max(r, c), RScalar(0));
    }
    s.a.resize(m_size, m_size);
    s.a.setFromTriplets(entries.begin(), entries.end());
    s.a.makeCompressed();
    s.slot.resize(m_r.size());
    for (std::size_t k = 0; k < m_r.size(); ++k) {
      const int r = std::min(place[m_r[k]], place[m_c[k]]), c = std::max(place[m_r[k]], place[m_c[k]]);
      const int* begin = s.a.innerIndexPtr() + s.a.outerIndexPtr()[c];
      const int* end = s.a.innerIndexPtr() + s.a.outerIndexPtr()[c + 1];
      s.slot[k] = static_cast<int>(std::lower_bound(begin, end, r) - s.a.innerIndexPtr());
    }
    s.ldlt.analyzePattern(s.a);
    s.patternR = m_r, s.patternC = m_c;
    s.analysed = true;
    s.z.resize(m_size), s.y.resize(m_size);
  }
  std::fill(s.a.valuePtr(), s.a.valuePtr() + s.a.nonZeros(), RScalar(0));
  for (std::size_t k = 0; k < m_v.size(); ++k) s.a.valuePtr()[s.slot[k]] += m_v[k];
  s.ldlt.factorize(s.a);
  return s.ldlt.info() == Eigen::Success;
}

void RJointSparse::Solve(RScalar* rhs, int n) {
  RImpl& s = *m_impl;
  const int* place = s.order.indices().data();
  s.z.setZero();
  for (int i = 0; i < n; ++i) s.z[place[i]] = rhs[i];
  s.y = s.ldlt.solve(s.z);
  for (int i = 0; i < n; ++i) rhs[i] = s.y[place[i]];
}

}  // namespace REngine::joints
