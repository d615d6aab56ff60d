// Reading a scene's JSON value by value (see RSceneJson.h).
#include "RSceneJson.h"

#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RConvexPolyhedron.h>
#include <REnginePhysics/RIntegrator.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace REngine::scenejson {

// Deepest nesting of JSON values a scene may have (the format needs about 8).
constexpr int kMaxSceneDepth = 64;


[[noreturn]] void Fail(std::string path, std::string problem) {
  throw Invalid{std::move(path), std::move(problem)};
}

std::string Field(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + '.' + key;
}
std::string Element(const std::string& path, std::size_t i) {
  return path + '[' + std::to_string(i) + ']';
}

// " (got <value>)", short enough to keep a message on one line, in bounded work whatever
// the value: a scene from a stranger may hold a 100 MB string or array where a number
// belongs, and dumping it whole (recursively, for nested arrays) to keep 40 characters
// cost gigabytes or the stack. Small flat arrays and objects are shown, others summarised.
std::string Got(const json& j) {
  constexpr std::size_t kShown = 40;
  std::string s;
  if (j.is_string()) {
    const std::string& text = j.get_ref<const std::string&>();
    s = json(text.substr(0, kShown)).dump(-1, ' ', true, json::error_handler_t::replace);
  } else if (j.is_array() || j.is_object()) {
    bool flat = j.size() <= 8;
    for (const json& e : j) flat = flat && !e.is_structured() && !e.is_string();
    s = flat ? j.dump(-1, ' ', true, json::error_handler_t::replace)
             : (j.is_array() ? "an array of " + std::to_string(j.size()) + " values"
                             : "an object of " + std::to_string(j.size()) + " fields");
  } else {
    s = j.dump();  // a number, true, false or null
  }
  if (s.size() > kShown) s = s.substr(0, kShown - 3) + "...";
  return " (got " + s + ")";
}

// nlohmann's messages start with "[json.exception.<kind>.<id>] ": noise to a scene author.
std::string WithoutPrefix(const char* what) {
  const char* end = std::strstr(what, "] ");
  return end ? end + 2 : what;
}

// ---------------------------------------------------------------------------------------
// JSON text -> document.
//
// nlohmann keeps the last of two equal keys, which would let `"mass": 1, ..., "mass": 2`
// pass silently, and its overflow error ("1e999") carries no position. Following the
// parse with a stack of open containers fixes both: duplicate keys are refused, and an
// error can name the path being read.
class PathTracker {
 public:
  bool operator()(int depth, json::parse_event_t event, json& parsed) {
    // The format nests about 8 deep (a compound's child's shape's points). A value nested
    // 100k deep (200 KB of brackets) overflowed the stack in recursive functions that work
    // on the parsed document; refusing it as it is read bounds every one of them.
    if (depth > kMaxSceneDepth) {
      Fail(Path(), "nested deeper than " + std::to_string(kMaxSceneDepth) + " levels");
    }
    switch (event) {
      case json::parse_event_t::object_start: m_open.push_back({false, 0, {}, {}}); break;
      case json::parse_event_t::array_start: m_open.push_back({true, 0, {}, {}}); break;
      case json::parse_event_t::key: {
        Container& c = m_open.back();
        c.key = parsed.get<std::string>();
        if (!c.keys.insert(c.key).second) Fail(Path(), "field given twice");
        break;
      }
      case json::parse_event_t::value: ElementDone(); break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        m_open.pop_back();
        ElementDone();
        break;
    }
    return true;
  }

  // Path of the value being read.
  std::string Path() const {
    std::string path;
    for (const Container& c : m_open) {
      if (c.isArray) path = Element(path, c.count);
      else if (!c.key.empty()) path = Field(path, c.key);
    }
    return path;
  }

 private:
  struct Container {
    bool isArray;
    std::size_t count;                   // array: elements read so far
    std::string key;                     // object: key of the value being read
    std::unordered_set<std::string> keys;  // object: keys read so far
  };
  void ElementDone() {
    if (!m_open.empty() && m_open.back().isArray) ++m_open.back().count;
  }
  std::vector<Container> m_open;
};

json ParseJson(const std::string& text) {
  // The callback is copied into a std::function; share the one tracker to read it after.
  auto tracker = std::make_shared<PathTracker>();
  try {
    return json::parse(
        text, [tracker](int d, json::parse_event_t e, json& p) { return (*tracker)(d, e, p); });
  } catch (const json::parse_error& e) {
    // "parse error at line 3, column 5: syntax error while parsing ..."
    const std::string what = WithoutPrefix(e.what());
    const std::string at = "parse error at ";
    Fail("", what.rfind(at, 0) == 0 ? "invalid JSON at " + what.substr(at.size())
                                    : "invalid JSON: " + what);
  } catch (const json::out_of_range& e) {
    // The one range error of parsing: a number too large for a double (1e999).
    Fail(tracker->Path(), "must be a finite number (" + WithoutPrefix(e.what()) + ")");
  } catch (const json::exception& e) {
    Fail(tracker->Path(), WithoutPrefix(e.what()));
  }
}

// ---------------------------------------------------------------------------------------
// Values. Each reader takes the value and its path and returns it converted or fails.


RScalar ReadNumber(const json& j, const std::string& path, const Interval& in) {
  if (j.is_number()) {
    const RScalar x = j.get<RScalar>();
    if (std::isfinite(x) && (in.loOpen ? x > in.lo : x >= in.lo) && x <= in.hi) return x;
  }
  Fail(path, std::string("must be ") + in.text + Got(j));
}
RScalar ReadPositive(const json& j, const std::string& path) {
  return ReadNumber(j, path, kPositive);
}
RScalar ReadUnitInterval(const json& j, const std::string& path) {
  return ReadNumber(j, path, kUnit);
}
RScalar ReadNonNegative(const json& j, const std::string& path) {
  return ReadNumber(j, path, kNonNegative);
}

RVec3 ReadVec3(const json& j, const std::string& path) { return ReadVector<3>(j, path); }

// Counts are integers; 600.0 and 6e2 are accepted as the integers they are, because JSON
// writers (Python's among them) may emit whole numbers in floating-point form.
std::uint64_t ReadInteger(const json& j, const std::string& path, std::uint64_t min,
                          std::uint64_t max) {
  bool ok = false;
  std::uint64_t n = 0;
  if (j.is_number_unsigned()) {
    n = j.get<std::uint64_t>(), ok = true;
  } else if (j.is_number_float()) {
    const double x = j.get<double>();
    // 2^64 is exact as a double; every whole double below it converts exactly.
    if (x >= 0 && x < 18446744073709551616.0 && x == std::floor(x)) {
      n = static_cast<std::uint64_t>(x), ok = true;
    }
  }  // a negative integer is never in range
  if (!ok || n < min || n > max) {
    const std::string range = max == std::numeric_limits<std::uint64_t>::max()
                                  ? ">= " + std::to_string(min)
                                  : "in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
    Fail(path, "must be an integer " + range + Got(j));
  }
  return n;
}

std::uint64_t ReadSteps(const json& j, const std::string& path) {
  return ReadInteger(j, path, 0, std::numeric_limits<std::uint64_t>::max());
}
int ReadIterations(const json& j, const std::string& path) {
  return static_cast<int>(ReadInteger(j, path, 1, RWorldSettings::kMaxSolverIterations));
}

std::uint32_t ReadBits(const json& j, const std::string& path) {
  return static_cast<std::uint32_t>(ReadInteger(j, path, 0, 0xFFFFFFFFu));
}

bool ReadBool(const json& j, const std::string& path) {
  if (!j.is_boolean()) Fail(path, "must be true or false" + Got(j));
  return j.get<bool>();
}

std::string ReadName(const json& j, const std::string& path) {
  if (!j.is_string() || j.get_ref<const std::string&>().empty()) {
    Fail(path, "must be a non-empty string" + Got(j));
  }
  // Names go into CSV files and terminals: a NUL, a line break or an escape sequence in one
  // would corrupt the trajectory or the screen; U+0080-U+009F (UTF-8 C2 80-9F) hold C1
  // controls, U+0085 a line break to some readers. (nlohmann has checked the UTF-8.)
  const std::string& text = j.get_ref<const std::string&>();
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto u = static_cast<unsigned char>(text[i]);
    const bool c1 = u == 0xc2 && i + 1 < text.size() &&
                    static_cast<unsigned char>(text[i + 1]) >= 0x80 &&
                    static_cast<unsigned char>(text[i + 1]) <= 0x9f;
    if (u < 0x20 || u == 0x7f || c1) {
      Fail(path, "must not contain control characters (U+0000-U+001F, U+007F-U+009F)" + Got(j));
    }
  }
  return j.get<std::string>();
}


RCombineMode ReadRestitutionCombine(const json& j, const std::string& path) {
  return ReadChoice<RCombineMode>(j, path,
                                  {{"min", RCombineMode::kMin},
                                   {"max", RCombineMode::kMax},
                                   {"product", RCombineMode::kProduct},
                                   {"average", RCombineMode::kAverage}});
}
RCombineMode ReadFrictionCombine(const json& j, const std::string& path) {
  return ReadChoice<RCombineMode>(j, path,
                                  {{"geometric", RCombineMode::kGeometric},
                                   {"min", RCombineMode::kMin},
                                   {"max", RCombineMode::kMax},
                                   {"product", RCombineMode::kProduct},
                                   {"average", RCombineMode::kAverage}});
}

// [w, x, y, z], normalised: authors write rounded quaternions ([0.7071, 0.7071, 0, 0]),
// and only a direction-less one (zero length) is an error.
RQuat ReadOrientation(const json& j, const std::string& path) {
  const std::optional<RQuat> q = QuatNormalized(QuatFromWXYZ(ReadVector<4>(j, path)));
  if (!q) Fail(path, "must be a quaternion [w, x, y, z] of non-zero length" + Got(j));
  return *q;
}

// ---------------------------------------------------------------------------------------
// Objects.

RScalar ReadFiniteNumber(const json& j, const std::string& path) {
  return ReadNumber(j, path, kFinite);
}

// {"linear": [bx, by, bz], "angular": [bx, by, bz]}, either absent meaning none locked.
RBodyLocks ReadLocks(const json& j, const std::string& path) {
  const Object locks(j, path, {"linear", "angular"});
  RBodyLocks l;
  auto read = [&](const char* key, std::array<bool, 3>& out) {
    if (!locks.Has(key)) return;
    const json& a = locks.Required(key);
    const std::string p = locks.PathOf(key);
    if (!a.is_array() || a.size() != 3) Fail(p, "must be an array of 3 booleans [x, y, z]" + Got(a));
    for (std::size_t i = 0; i < 3; ++i) out[i] = ReadBool(a[i], Element(p, i));
  };
  read("linear", l.linear);
  read("angular", l.angular);
  return l;
}


RShape ReadShape(const json& j, const std::string& path, const RSceneLimits& limits) {
  const Object shape(j, path, {"type", "half_extents", "radius", "points", "half_height", "children", "vertices",
                               "triangles"});
  RShape s;
  s.type = ReadChoice<RShapeType>(shape.Required("type"), shape.PathOf("type"),
                                  {{"box", RShapeType::kBox},
                                   {"sphere", RShapeType::kSphere},
                                   {"hull", RShapeType::kHull},
                                   {"capsule", RShapeType::kCapsule},
                                   {"cylinder", RShapeType::kCylinder},
                                   {"compound", RShapeType::kCompound},
                                   {"mesh", RShapeType::kMesh}});
  switch (s.type) {
    case RShapeType::kBox:
      shape.AllowOnly({"type", "half_extents"});
      s.halfExtents = ReadVector<3>(shape.Required("half_extents"), shape.PathOf("half_extents"),
                                    kPositive);
      break;
    case RShapeType::kSphere:
      shape.AllowOnly({"type", "radius"});
      s.radius = ReadPositive(shape.Required("radius"), shape.PathOf("radius"));
      break;
    case RShapeType::kCapsule:
    case RShapeType::kCylinder:
      shape.AllowOnly({"type", "radius", "half_height"});
      s.radius = ReadPositive(shape.Required("radius"), shape.PathOf("radius"));
      s.halfHeight = ReadPositive(shape.Required("half_height"), shape.PathOf("half_height"));
      break;
    case RShapeType::kCompound: {
      shape.AllowOnly({"type", "children"});
      const json& children = shape.Required("children");
      const std::string childrenPath = shape.PathOf("children");
      if (!children.is_array() || children.empty()) {
        Fail(childrenPath, "must be a non-empty array of children {\"shape\", \"position\", \"orientation\", "
                           "\"density\"}" + Got(children));
      }
      if (children.size() > RShape::kMaxChildren) {
        Fail(childrenPath, "has " + std::to_string(children.size()) + " children; at most " +
                               std::to_string(RShape::kMaxChildren) + " are allowed");
      }
      for (std::size_t i = 0; i < children.size(); ++i) {
        const std::string childPath = Element(childrenPath, i);
        const Object child(children[i], childPath, {"shape", "position", "orientation", "density"});
        RCompoundChild c;
        c.shape = ReadShape(child.Required("shape"), child.PathOf("shape"), limits);
        if (c.shape.type == RShapeType::kCompound || c.shape.type == RShapeType::kMesh) {
          Fail(child.PathOf("shape") + ".type", "a compound or a mesh cannot be a child (children are convex)");
        }
        c.position_S = child.Get("position", c.position_S, ReadVec3);
        c.q_SC = child.Get("orientation", c.q_SC, ReadOrientation);
        c.density = child.Get("density", c.density, ReadPositive);
        s.children.push_back(std::move(c));
      }
      break;
    }
    case RShapeType::kMesh: {
      // The lists' shapes here; indices in range, degenerate triangles and coordinates are
      // checked where the mesh is built (RTriangleMesh), named by the same paths.
      shape.AllowOnly({"type", "vertices", "triangles"});
      const json& vertices = shape.Required("vertices");
      const json& triangles = shape.Required("triangles");
      const std::string verticesPath = shape.PathOf("vertices"), trianglesPath = shape.PathOf("triangles");
      if (!vertices.is_array() || vertices.size() < 3) {
        Fail(verticesPath, "must be an array of at least 3 points [x, y, z]" + Got(vertices));
      }
      if (!triangles.is_array() || triangles.empty()) {
        Fail(trianglesPath, "must be a non-empty array of index triples [i, j, k]" + Got(triangles));
      }
      for (const auto& [list, listPath] : {std::pair{&vertices, verticesPath}, std::pair{&triangles, trianglesPath}}) {
        if (list->size() > limits.maxMeshTriangles) {
          Fail(listPath, "has " + std::to_string(list->size()) + " entries; at most " +
                             std::to_string(limits.maxMeshTriangles) + " are allowed");
        }
      }
      s.points.reserve(vertices.size());
      for (std::size_t i = 0; i < vertices.size(); ++i) s.points.push_back(ReadVec3(vertices[i], Element(verticesPath, i)));
      s.triangles.reserve(triangles.size());
      for (std::size_t i = 0; i < triangles.size(); ++i) {
        const std::string at = Element(trianglesPath, i);
        if (!triangles[i].is_array() || triangles[i].size() != 3) Fail(at, "must be 3 vertex indices [i, j, k]" + Got(triangles[i]));
        std::array<std::uint32_t, 3> t;
        for (std::size_t k = 0; k < 3; ++k) t[k] = ReadBits(triangles[i][k], Element(at, k));
        s.triangles.push_back(t);
      }
      break;
    }
    case RShapeType::kHull: {
      shape.AllowOnly({"type", "points"});
      const json& points = shape.Required("points");
      const std::string pointsPath = shape.PathOf("points");
      if (!points.is_array() || points.size() < 4) {
        Fail(pointsPath, "must be an array of at least 4 points [x, y, z]" + Got(points));
      }
      if (points.size() > limits.maxHullPoints) {
        Fail(pointsPath, "has " + std::to_string(points.size()) + " points; at most " +
                             std::to_string(limits.maxHullPoints) + " are allowed");
      }
      for (std::size_t i = 0; i < points.size(); ++i) {
        s.points.push_back(ReadVec3(points[i], Element(pointsPath, i)));
      }
      // Building the hull is the test that the points span a solid: one definition of
      // "flat" (RConvexPolyhedron's), so a scene that loads also creates its bodies.
      try {
        (void)RConvexPolyhedron::Hull(s.points);
      } catch (const RHullError& e) {
        Fail(pointsPath, e.what());
      }
      break;
    }
  }
  return s;
}

// A body, and the names in its "ignore" list (resolved once all names are known, since a
// body may name one that comes after it).
RBodyDef ReadBody(const json& j, const std::string& path, std::vector<std::string>& ignore,
                  const RSceneLimits& limits) {
  const Object body(j, path,
                    {"name", "shape", "static", "kind", "mass", "density", "position",
                     "orientation", "velocity", "angular_velocity", "restitution", "friction",
                     "responds", "ignore", "category", "mask", "linear_damping",
                     "angular_damping", "gravity_scale", "locks", "one_way"});
  RBodyDef def;
  def.name = ReadName(body.Required("name"), body.PathOf("name"));
  def.shape = ReadShape(body.Required("shape"), body.PathOf("shape"), limits);
  const bool isStatic = body.Get("static", false, ReadBool);
  def.kind = isStatic ? RBodyKind::kStatic : RBodyKind::kDynamic;
  if (body.Has("kind")) {
    def.kind = ReadChoice<RBodyKind>(body.Required("kind"), body.PathOf("kind"),
                                     {{"dynamic", RBodyKind::kDynamic},
                                      {"static", RBodyKind::kStatic},
                                      {"kinematic", RBodyKind::kKinematic}});
    // "static": false with "kind": "static" says two things, as "static": true with another
    // kind does; "static": false beside "dynamic" or "kinematic" agrees.
    if (body.Has("static") && isStatic != (def.kind == RBodyKind::kStatic)) {
      Fail(body.PathOf("kind"), std::string("contradicts \"static\": ") +
                                    (isStatic ? "true" : "false") + Got(body.Required("kind")));
    }
  }
  def.linearDamping = body.Get("linear_damping", def.linearDamping, ReadNonNegative);
  def.angularDamping = body.Get("angular_damping", def.angularDamping, ReadNonNegative);
  def.gravityScale = body.Get("gravity_scale", def.gravityScale, ReadFiniteNumber);
  if (body.Has("locks")) def.locks = ReadLocks(body.Required("locks"), body.PathOf("locks"));
  if (body.Has("mass") && body.Has("density")) {
    Fail(body.PathOf("density"), "give mass or density, not both");
  }
  // A static body's mass is checked, though unused, so that toggling "static" never turns
  // a loadable scene into a broken one.
  def.mass = body.Get("mass", def.mass, ReadPositive);
  def.density = body.Get("density", def.density, ReadPositive);
  def.position_W = body.Get("position", def.position_W, ReadVec3);
  def.q_WS = body.Get("orientation", def.q_WS, ReadOrientation);
  def.velocity_W = body.Get("velocity", def.velocity_W, ReadVec3);
  def.angularVelocity_W = body.Get("angular_velocity", def.angularVelocity_W, ReadVec3);
  def.restitution = body.Get("restitution", RScene::kDefaultRestitution, ReadUnitInterval);
  def.friction = body.Get("friction", def.friction, ReadNonNegative);
  def.responds = body.Get("responds", def.responds, ReadBool);
  def.oneWay = body.Get("one_way", def.oneWay, ReadBool);
  def.category = body.Get("category", def.category, ReadBits);
  def.mask = body.Get("mask", def.mask, ReadBits);
  if (body.Has("ignore")) ignore = ReadNames(body.Required("ignore"), body.PathOf("ignore"));
  return def;
}

std::vector<std::string> ReadNames(const json& j, const std::string& path) {
  if (!j.is_array()) Fail(path, "must be an array of body names" + Got(j));
  std::vector<std::string> names;
  for (std::size_t i = 0; i < j.size(); ++i) names.push_back(ReadName(j[i], Element(path, i)));
  return names;
}

}  // namespace REngine::scenejson
