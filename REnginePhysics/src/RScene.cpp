#include <REnginePhysics/RScene.h>

#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RConvexPolyhedron.h>

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

namespace REngine {

namespace {

using json = nlohmann::json;

// Deepest nesting of JSON values a scene may have (the format needs about 8).
constexpr int kMaxSceneDepth = 64;

// A problem at a JSON path. Thrown by the readers below and turned into an RSceneError,
// with the file name, at the API boundary, so that no reader needs to know the file.
struct Invalid {
  std::string path;
  std::string problem;
};

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

// The numbers a field accepts, and how an error message states it.
struct Interval {
  RScalar lo, hi;
  bool loOpen;
  const char* text;
};
constexpr RScalar kInf = std::numeric_limits<RScalar>::infinity();
constexpr Interval kFinite{-kInf, kInf, false, "a finite number"};
constexpr Interval kPositive{0, kInf, true, "a finite number > 0"};
constexpr Interval kNonNegative{0, kInf, false, "a finite number >= 0"};
constexpr Interval kUnit{0, 1, false, "a number in [0, 1]"};

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

template <int N>
Eigen::Matrix<RScalar, N, 1> ReadVector(const json& j, const std::string& path,
                                        const Interval& in = kFinite) {
  if (!j.is_array() || j.size() != N) {
    Fail(path, "must be an array of " + std::to_string(N) + " numbers" + Got(j));
  }
  Eigen::Matrix<RScalar, N, 1> v;
  for (int i = 0; i < N; ++i) v[i] = ReadNumber(j[i], Element(path, i), in);
  return v;
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
  return static_cast<int>(ReadInteger(j, path, 1, INT_MAX));
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

// One of a fixed set of strings, mapped to its value.
template <class T>
T ReadChoice(const json& j, const std::string& path,
             std::initializer_list<std::pair<const char*, T>> choices) {
  if (j.is_string()) {
    for (const auto& [name, value] : choices) {
      if (j.get_ref<const std::string&>() == name) return value;
    }
  }
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "\"" : ", \"") + std::string(c.first) + '"';
  Fail(path, "must be one of " + list + Got(j));
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

// A JSON object at a path, whose fields are all known (the format refuses unknown fields
// so that a misspelt one never passes as a default), with typed reads of its fields.
class Object {
 public:
  Object(const json& j, std::string path, std::initializer_list<const char*> fields)
      : m_j(j), m_path(std::move(path)) {
    if (!j.is_object()) {
      Fail(m_path, (m_path.empty() ? "the scene must be a JSON object" : "must be an object") +
                       Got(j));
    }
    AllowOnly(fields);
  }

  // Narrows the known fields once more is known (a shape's fields depend on its type).
  void AllowOnly(std::initializer_list<const char*> fields) const {
    for (const auto& item : m_j.items()) {
      const bool known = std::any_of(fields.begin(), fields.end(),
                                     [&](const char* f) { return item.key() == f; });
      if (!known) {
        std::string list;
        for (const char* f : fields) list += (list.empty() ? "" : ", ") + std::string(f);
        Fail(PathOf(item.key()), "unknown field (the fields here are: " + list + ")");
      }
    }
  }

  std::string PathOf(const std::string& key) const { return Field(m_path, key); }
  bool Has(const char* key) const { return m_j.contains(key); }

  const json& Required(const char* key) const {
    const auto it = m_j.find(key);
    if (it == m_j.end()) Fail(PathOf(key), "required field is missing");
    return *it;
  }

  // read(value, path) of the field, or `fallback` when it is absent.
  template <class T, class Read>
  T Get(const char* key, T fallback, Read read) const {
    const auto it = m_j.find(key);
    return it == m_j.end() ? fallback : T(read(*it, PathOf(key)));
  }

 private:
  const json& m_j;
  std::string m_path;
};

RShape ReadShape(const json& j, const std::string& path, const RSceneLimits& limits) {
  const Object shape(j, path, {"type", "half_extents", "radius", "points"});
  RShape s;
  s.type = ReadChoice<RShapeType>(shape.Required("type"), shape.PathOf("type"),
                                  {{"box", RShapeType::kBox},
                                   {"sphere", RShapeType::kSphere},
                                   {"hull", RShapeType::kHull}});
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
                    {"name", "shape", "static", "mass", "density", "position", "orientation",
                     "velocity", "angular_velocity", "restitution", "friction", "responds",
                     "ignore"});
  RBodyDef def;
  def.name = ReadName(body.Required("name"), body.PathOf("name"));
  def.shape = ReadShape(body.Required("shape"), body.PathOf("shape"), limits);
  def.isStatic = body.Get("static", def.isStatic, ReadBool);
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
  def.restitution = body.Get("restitution", def.restitution, ReadUnitInterval);
  def.friction = body.Get("friction", def.friction, ReadNonNegative);
  def.responds = body.Get("responds", def.responds, ReadBool);
  if (body.Has("ignore")) {
    const json& names = body.Required("ignore");
    const std::string ignorePath = body.PathOf("ignore");
    if (!names.is_array()) Fail(ignorePath, "must be an array of body names" + Got(names));
    for (std::size_t i = 0; i < names.size(); ++i) {
      ignore.push_back(ReadName(names[i], Element(ignorePath, i)));
    }
  }
  return def;
}

RScene ReadScene(const json& doc, const RSceneLimits& limits) {
  const Object root(doc, "",
                    {"format", "gravity", "dt", "steps", "restitution_combine",
                     "friction_combine", "solver", "bodies"});
  RScene scene;
  if (root.Has("format")) {
    const json& format = root.Required("format");
    if (format != "rengine-scene/1") {
      Fail("format", "must be \"rengine-scene/1\", the format this build reads" + Got(format));
    }
  }
  RWorldSettings& settings = scene.settings;
  settings.gravity_W = root.Get("gravity", settings.gravity_W, ReadVec3);
  scene.dt = root.Get("dt", scene.dt, ReadPositive);
  scene.steps = root.Get("steps", scene.steps, ReadSteps);
  settings.restitutionCombine =
      root.Get("restitution_combine", settings.restitutionCombine, ReadRestitutionCombine);
  settings.frictionCombine =
      root.Get("friction_combine", settings.frictionCombine, ReadFrictionCombine);
  if (root.Has("solver")) {
    const Object solver(root.Required("solver"), "solver", {"iterations", "sleeping"});
    settings.solverIterations = solver.Get("iterations", settings.solverIterations, ReadIterations);
    settings.shortcuts.sleeping = solver.Get("sleeping", settings.shortcuts.sleeping, ReadBool);
  }

  const json& bodies = root.Required("bodies");
  if (!bodies.is_array()) Fail("bodies", "must be an array of bodies" + Got(bodies));
  if (bodies.size() > limits.maxBodies) {
    Fail("bodies", "has " + std::to_string(bodies.size()) + " bodies; at most " +
                       std::to_string(limits.maxBodies) + " are allowed");
  }
  std::vector<std::vector<std::string>> ignoreNames(bodies.size());
  std::unordered_map<std::string, std::size_t> indexOf;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const std::string path = Element("bodies", i);
    scene.bodies.push_back(ReadBody(bodies[i], path, ignoreNames[i], limits));
    const auto [it, isNew] = indexOf.emplace(scene.bodies.back().name, i);
    if (!isNew) {
      Fail(Field(path, "name"), "\"" + it->first + "\" is already the name of " +
                                    Element("bodies", it->second));
    }
  }

  scene.ignore.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    for (std::size_t k = 0; k < ignoreNames[i].size(); ++k) {
      const std::string path = Element(Field(Element("bodies", i), "ignore"), k);
      const auto it = indexOf.find(ignoreNames[i][k]);
      if (it == indexOf.end()) Fail(path, "no body is named \"" + ignoreNames[i][k] + "\"");
      if (it->second == i) Fail(path, "a body cannot ignore itself");
      scene.ignore[i].push_back(it->second);
      scene.ignore[it->second].push_back(i);
    }
  }
  for (std::vector<std::size_t>& list : scene.ignore) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return scene;
}

}  // namespace

RSceneError::RSceneError(std::string file, std::string jsonPath, std::string problem)
    : std::runtime_error(file + ": " + (jsonPath.empty() ? "" : jsonPath + ": ") + problem),
      m_file(std::move(file)),
      m_jsonPath(std::move(jsonPath)),
      m_problem(std::move(problem)) {}

void CheckSceneLimits(const RScene& scene, const RSceneLimits& limits) {
  if (scene.bodies.size() > limits.maxBodies) {
    throw RSceneError(scene.fileName, "bodies",
                      "has " + std::to_string(scene.bodies.size()) + " bodies; at most " +
                          std::to_string(limits.maxBodies) + " are allowed");
  }
  if (scene.steps > limits.maxSteps) {
    throw RSceneError(scene.fileName, "steps",
                      "must be at most " + std::to_string(limits.maxSteps) + " (got " +
                          std::to_string(scene.steps) + ")");
  }
  if (static_cast<double>(scene.steps) * static_cast<double>(scene.bodies.size()) >
      limits.maxBodySteps) {
    char limit[32];
    std::snprintf(limit, sizeof limit, "%.3g", limits.maxBodySteps);
    throw RSceneError(scene.fileName, "steps",
                      std::to_string(scene.steps) + " steps of " +
                          std::to_string(scene.bodies.size()) + " bodies exceed " + limit +
                          " body-steps");
  }
}

RScene ParseScene(const std::string& jsonText, const std::string& fileNameForMessages,
                  const RSceneLimits& limits) {
  RScene scene;
  try {
    scene = ReadScene(ParseJson(jsonText), limits);
  } catch (const Invalid& e) {
    throw RSceneError(fileNameForMessages, e.path, e.problem);
  }
  scene.fileName = fileNameForMessages;
  CheckSceneLimits(scene, limits);
  return scene;
}

RScene LoadScene(const std::string& path, const RSceneLimits& limits) {
  struct Close {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  const std::unique_ptr<std::FILE, Close> file(std::fopen(path.c_str(), "rb"));
  if (!file) throw RSceneError(path, "", std::string("cannot open: ") + std::strerror(errno));
  std::string text;
  char chunk[1 << 16];
  std::size_t n;
  while ((n = std::fread(chunk, 1, sizeof chunk, file.get())) > 0) {
    text.append(chunk, n);
    if (text.size() > limits.maxFileBytes) {
      throw RSceneError(path, "", "larger than " + std::to_string(limits.maxFileBytes) +
                                      " bytes, the most a scene may be");
    }
  }
  // A directory opens but does not read (EISDIR).
  if (std::ferror(file.get())) {
    throw RSceneError(path, "", std::string("cannot read: ") + std::strerror(errno));
  }
  return ParseScene(text, path, limits);
}

std::vector<RRigidBody> CreateBodies(const RScene& scene) {
  std::vector<RRigidBody> bodies;
  bodies.reserve(scene.bodies.size());
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    try {
      RBodyDef def = scene.bodies[i];
      def.id = static_cast<std::uint32_t>(i);
      for (std::size_t j : scene.ignore[i]) def.ignore.push_back(static_cast<std::uint32_t>(j));
      bodies.emplace_back(def);
    } catch (const RBodyError& e) {
      throw RSceneError(scene.fileName, Field(Element("bodies", i), e.Field()), e.Problem());
    }
  }
  return bodies;
}

}  // namespace REngine
