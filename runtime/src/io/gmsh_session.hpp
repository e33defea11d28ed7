/// \file gmsh_session.hpp
/// Internal (not installed): Gmsh keeps global state, so every use of its
/// API (reading .msh surfaces, filling the octree mesher's gap) holds one
/// process-wide lock and one initialised session, finalised on scope exit.
#ifndef TENSORMASS_GMSH_SESSION_HPP
#define TENSORMASS_GMSH_SESSION_HPP

#include <gmsh.h>

#include <mutex>

namespace tensormass::detail {

inline std::mutex& gmsh_mutex() {
  static std::mutex mutex;
  return mutex;
}

/// Locks Gmsh for this thread and initialises it silently; finalises on exit.
class GmshSession {
 public:
  GmshSession() : lock_(gmsh_mutex()) {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
  }
  ~GmshSession() {
    try {
      gmsh::finalize();
    } catch (...) {  // nothing sensible to do while unwinding
    }
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

 private:
  std::lock_guard<std::mutex> lock_;
};

}  // namespace tensormass::detail

#endif
