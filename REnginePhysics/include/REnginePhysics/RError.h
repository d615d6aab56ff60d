// RError: the one base of every exception REngine throws for input it refuses (a body, joint,
// shape, query, scene file, saved state, handle or step argument), so a game can catch them
// all in one place and still learn which field was wrong.
//
//   try { bodies.Add(def); } catch (const RError& e) { log(e.Field(), e.Problem()); }
//
// Each subsystem throws its own type derived from it (RBodyError, RJointError, RHullError,
// RMeshError, RQueryError, RHandleError, RStateError, RSceneError); the integrator's own
// refusals (dt, RWorldSettings) are RError itself. It derives from std::runtime_error: the
// engine reports bad values met at run time (a scene file, a game's numbers), and a catch of
// std::exception or std::runtime_error takes every engine error too.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace REngine {

class RError : public std::runtime_error {
 public:
  // what() is "<field>: <problem>", or the problem alone when field is empty.
  RError(std::string field, std::string problem)
      : std::runtime_error(field.empty() ? problem : field + ": " + problem),
        m_field(std::move(field)),
        m_problem(std::move(problem)) {}
  // With what() given in full (a message with more context: a scene's file name, the call
  // that refused).
  RError(std::string field, std::string problem, const std::string& what)
      : std::runtime_error(what), m_field(std::move(field)), m_problem(std::move(problem)) {}

  // The field or argument refused, as the API or the scene format names it
  // ("shape.radius", "bodies[3].mass", "dt"); empty when no one field is at fault.
  const std::string& Field() const noexcept { return m_field; }
  // What is wrong with it ("must be a finite number > 0 (got -1)").
  const std::string& Problem() const noexcept { return m_problem; }

 private:
  std::string m_field, m_problem;
};

}  // namespace REngine
