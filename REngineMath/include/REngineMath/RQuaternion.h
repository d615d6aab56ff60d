// Quaternion helpers for rotations. A quaternion q_WB maps body-frame vectors to world
// frame: v_W = q_WB * v_B. All quaternions here are unit quaternions unless said otherwise.
#pragma once

#include <REngineMath/RMath.h>

#include <optional>

namespace REngine {

// Exponential map: the unit quaternion of the rotation by |theta| rad about theta/|theta|.
// Accurate to rounding for any angle, including |theta| -> 0 (uses a series for sin(x)/x
// below 1e-4 rad, where the closed form would lose digits).
RQuat QuatExp(const RVec3& theta);

// Inverse of QuatExp: the rotation vector (rad) with angle in [0, pi]. Picks the shorter of
// q and -q, which are the same rotation.
RVec3 QuatLog(const RQuat& q);

// Rotation by `angle` rad about the unit vector `axis`.
RQuat QuatAxisAngle(const RVec3& axis, RScalar angle);

// Angle (rad, in [0, pi]) of the rotation that takes a to b: the distance between two
// orientations. Accurate for tiny angles (atan2 form, not acos).
RScalar QuatAngleBetween(const RQuat& a, const RQuat& b);

// The minimal rotation taking unit vector `from` to unit vector `to`. For antiparallel
// vectors, a half turn about an axis perpendicular to `from`.
RQuat QuatFromTo(const RVec3& from, const RVec3& to);

// q / |q|, or nothing when q has a non-finite component or is zero: the only quaternions
// without a direction (any non-zero scale works, 1e-200 or 1e200). Callers decide whether
// that is a user error or a bug; nothing is silently turned into the identity.
std::optional<RQuat> QuatNormalized(const RQuat& q);

// [w, x, y, z] as REngine's files write them.
inline RVec4 QuatToWXYZ(const RQuat& q) { return RVec4(q.w(), q.x(), q.y(), q.z()); }
inline RQuat QuatFromWXYZ(const RVec4& v) { return RQuat(v[0], v[1], v[2], v[3]); }

}  // namespace REngine
