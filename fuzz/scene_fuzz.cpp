// libFuzzer target: the bytes are the text of a scene file, and the target does what
// `hemicontact solve` does before solving — parse (duplicate keys, overflowing numbers, nesting),
// validate against the schema, read the solve options, build the mesh, the boundary parts and the
// model (assembly, contact nodes, laws, scale and memory checks) — at tiny sizes.
//
// The acceptable outcomes are success and hemicontact::Error (a clear message and an exit code).
// Anything else is a finding: another exception (a nlohmann::json type_error the validation let
// through, std::out_of_range, bad_alloc, ...) aborts, and so does any AddressSanitizer or
// UndefinedBehaviorSanitizer report, which the build enables (scripts/run-sanitizers.sh).
//
// Run: build-san/fuzz/hemicontact_scene_fuzz -dict=fuzz/scene.dict fuzz/corpus -max_total_time=60
#include <hemicontact/core/error.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace {

// Cells the mesh would have: the target builds only tiny meshes, so that one input takes
// milliseconds (the generators and assembly are linear in the mesh; their bugs show at n = 1).
double cells(const nlohmann::json& mesh) {
  const double nx = mesh.at("nx").get<double>(), ny = mesh.at("ny").get<double>();
  return mesh.at("type") == "box" ? nx * ny * mesh.at("nz").get<double>() : nx * ny;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hemicontact;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const nlohmann::json scene = load_scene_text(text, "fuzz.json");
    (void)solve_options_from_scene(scene);
    const nlohmann::json& mesh = scene.at("mesh");
    // No files: a gmsh scene would read whatever path the input names.
    if (mesh.at("type") == "gmsh" || cells(mesh) > 64) return 0;
    const Model md = build_model(scene, "/nonexistent-scene-dir");
    (void)md;
  } catch (const Error&) {
    // the clear-message path: fine
  } catch (const std::exception& e) {
    std::fprintf(stderr, "scene_fuzz: escaped exception (not hemicontact::Error): %s\n", e.what());
    std::abort();
  }
  return 0;
}
