// A trajectory as rengine-sim writes it (docs/scene-format.md, "Trajectory CSV"):
// one row per body per written step, `step,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz`.
// Read into one list of samples per body (a body's rows run from the step it exists at to
// the step it is removed), and posed at any time between them for drawing.
#pragma once

#include <REngineMath/RMath.h>

#include <istream>
#include <stdexcept>
#include <string>
#include <vector>

namespace rengineview {

using REngine::RQuat;
using REngine::RVec3;

// A row that is not the format's: "FILE:LINE: problem".
class TrajectoryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct TrajectorySample {
  double time = 0;                   // s
  RVec3 position_W = RVec3::Zero();  // the body's frame (the scene's pose), world, m
  RQuat q_WS = RQuat::Identity();
};

class Trajectory {
 public:
  // Throws TrajectoryError naming `name` and the line: a header other than the format's, a
  // row without its 16 fields, a number that does not parse or is not finite, a zero
  // quaternion, time running backwards for a body.
  static Trajectory Read(std::istream& in, const std::string& name);
  static Trajectory ReadFile(const std::string& path);

  // Body names in the order they first appear (scene order, then added bodies).
  const std::vector<std::string>& Bodies() const { return m_names; }
  const std::vector<TrajectorySample>& Samples(std::size_t body) const { return m_samples[body]; }
  double StartTime() const { return m_start; }
  double EndTime() const { return m_end; }
  std::size_t Rows() const { return m_rows; }

  // The body's pose at time t, between the samples either side (position linearly, rotation
  // by slerp: the rows are a step or --every K steps apart, so this is a drawing's
  // interpolation, not the motion's). False when t is outside the body's rows (not yet
  // added, or removed).
  bool PoseAt(std::size_t body, double t, RVec3& position_W, RQuat& q_WS) const;

 private:
  std::vector<std::string> m_names;
  std::vector<std::vector<TrajectorySample>> m_samples;
  double m_start = 0, m_end = 0;
  std::size_t m_rows = 0;
};

}  // namespace rengineview
