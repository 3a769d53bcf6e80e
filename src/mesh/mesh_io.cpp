#include <hemicontact/mesh/gmsh_import.hpp>

#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>

// read_gmsh() for builds without the Gmsh API. CMake compiles src/mesh/gmsh_*.cpp only when Gmsh
// was found, so this file must not start with "gmsh_"; with Gmsh it defines nothing.

namespace hemicontact {

#if !HEMICONTACT_HAS_GMSH
Mesh read_gmsh(const std::string& path, bool) {
  throw Error("gmsh file '" + path + "': Gmsh .msh import was not compiled in (install libgmsh-dev and rebuild)");
}
#endif

}  // namespace hemicontact
