#include "Trajectory.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <unordered_map>

namespace rengineview {

namespace {
constexpr const char* kHeader = "step,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz";
constexpr std::size_t kFields = 16;
}  // namespace

Trajectory Trajectory::ReadFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw TrajectoryError(path + ": cannot be read");
  return Read(in, path);
}

Trajectory Trajectory::Read(std::istream& in, const std::string& name) {
  Trajectory t;
  std::unordered_map<std::string, std::size_t> index;
  std::string line;
  std::size_t lineNo = 0;
  auto fail = [&](const std::string& problem) -> TrajectoryError {
    return TrajectoryError(name + ":" + std::to_string(lineNo) + ": " + problem);
  };
  if (!std::getline(in, line)) throw TrajectoryError(name + ": empty");
  ++lineNo;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line != kHeader) throw fail("the header is not `" + std::string(kHeader) + "`");
  std::vector<std::string> fields;
  t.m_start = std::numeric_limits<double>::infinity();
  t.m_end = -std::numeric_limits<double>::infinity();
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    fields.clear();
    std::size_t from = 0;
    for (std::size_t comma; (comma = line.find(',', from)) != std::string::npos; from = comma + 1)
      fields.push_back(line.substr(from, comma - from));
    fields.push_back(line.substr(from));
    if (fields.size() != kFields)
      throw fail(std::to_string(fields.size()) + " fields, not " + std::to_string(kFields));
    double v[kFields] = {};
    for (std::size_t k : {std::size_t(1), std::size_t(3), std::size_t(4), std::size_t(5),
                          std::size_t(6), std::size_t(7), std::size_t(8), std::size_t(9)}) {
      char* end = nullptr;
      v[k] = std::strtod(fields[k].c_str(), &end);
      if (fields[k].empty() || *end || !std::isfinite(v[k]))
        throw fail("field " + std::to_string(k + 1) + " is not a finite number: `" + fields[k] +
                   "`");
    }
    TrajectorySample s;
    s.time = v[1];
    s.position_W = RVec3(v[3], v[4], v[5]);
    s.q_WS = RQuat(v[6], v[7], v[8], v[9]);
    if (s.q_WS.norm() == 0) throw fail("a zero quaternion");
    s.q_WS.normalize();
    auto [it, added] = index.emplace(fields[2], t.m_names.size());
    if (added) t.m_names.push_back(fields[2]), t.m_samples.emplace_back();
    std::vector<TrajectorySample>& samples = t.m_samples[it->second];
    if (!samples.empty() && s.time < samples.back().time)
      throw fail("time runs backwards for body `" + fields[2] + "`");
    samples.push_back(s);
    t.m_start = std::min(t.m_start, s.time);
    t.m_end = std::max(t.m_end, s.time);
    ++t.m_rows;
  }
  if (t.m_rows == 0) throw TrajectoryError(name + ": no rows");
  return t;
}

bool Trajectory::PoseAt(std::size_t body, double t, RVec3& position_W, RQuat& q_WS) const {
  const std::vector<TrajectorySample>& s = m_samples[body];
  if (s.empty() || t < s.front().time || t > s.back().time) return false;
  // The first sample after t (binary search: a long run has many rows per body).
  auto after = std::upper_bound(s.begin(), s.end(), t,
                                [](double x, const TrajectorySample& a) { return x < a.time; });
  if (after == s.end()) {
    position_W = s.back().position_W, q_WS = s.back().q_WS;
    return true;
  }
  const TrajectorySample& b = *after;
  const TrajectorySample& a = *(after - 1);
  const double f = b.time > a.time ? (t - a.time) / (b.time - a.time) : 0;
  position_W = a.position_W + f * (b.position_W - a.position_W);
  q_WS = a.q_WS.slerp(f, b.q_WS);
  return true;
}

}  // namespace rengineview
