// The Python module's compiled part, hemicontact._hemicontact: scenes, solves, the studies. The
// package python/hemicontact/__init__.py wraps it (Result's properties, meshio export, docs).
//
// Every call goes through the same library functions as the CLI (src/cli): load_scene /
// load_scene_text with --set assignments, solve_scene and write_scene_solve (studies/scene_solve.hpp,
// the CLI's and hemicontact-mpi's solve too), find_minima + minima_json, run_convergence +
// convergence_json. What differs is the host's side:
//  - the GIL is released for the whole solve or study (build, solve, report), so solves in Python
//    threads run side by side;
//  - Ctrl-C: on the main thread the solve polls Python's signal handlers (core/interrupt.hpp) and
//    unwinds with the handler's exception (KeyboardInterrupt);
//  - log lines go to logging.getLogger("hemicontact") instead of stderr;
//  - arrays are copied into NumPy's own buffers: they outlive the Result.
#include <hemicontact/config.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/interrupt.hpp>
#include <hemicontact/core/log.hpp>
#include <hemicontact/core/process.hpp>
#include <hemicontact/nlp/backend.hpp>
#include <hemicontact/output/output_dir.hpp>
#include <hemicontact/output/report.hpp>
#include <hemicontact/output/solve_files.hpp>
#include <hemicontact/output/study_writers.hpp>
#include <hemicontact/output/vtk_writer.hpp>
#include <hemicontact/studies/scene_solve.hpp>
#include <hemicontact/studies/study_json.hpp>
#include <hemicontact/scene/build_model.hpp>
#include <hemicontact/scene/config.hpp>
#include <hemicontact/solver/engine_choice.hpp>
#include <hemicontact/studies/petsc_process.hpp>
#include <hemicontact/solver/adapt.hpp>
#include <hemicontact/solver/solve.hpp>
#include <hemicontact/studies/convergence.hpp>
#include <hemicontact/studies/minima.hpp>

// The random scenes of the stress and default-settings studies (seeds -> --set assignments), so
// that the Python benchmarks and tests draw exactly the scenes the C++ studies do.
#include <hemicontact/studies/random_scenes.hpp>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pythread.h>

#include <dlfcn.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace py = pybind11;
using json = nlohmann::json;

namespace hemicontact::python {
namespace {

// ------------------------------------------------------------------ JSON <-> Python
// Through Python's json module: the report and scene dicts are small (the report of fig2 at
// n = 256 is ~200 KB of text), and json.loads gives exactly the dict a reader of report.json gets.
py::object py_json_loads(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

py::object to_py(const json& j) { return py_json_loads(j.dump()); }

std::string py_json_dumps(py::handle value) {
  return py::module_::import("json").attr("dumps")(value).cast<std::string>();
}

// ------------------------------------------------------------------ interrupts
unsigned long g_main_thread = 0;  // PyThread_get_thread_ident() of the thread that imported us

// The interrupt check of one call on the main thread: at most every 20 ms it takes the GIL and
// runs Python's pending signal handlers (Ctrl-C's raises KeyboardInterrupt); the exception is
// kept (fetched, so no Python error is pending while the GIL is released) and raised once the
// solve has unwound.
class SignalRelay {
 public:
  SignalRelay() = default;
  SignalRelay(const SignalRelay&) = delete;
  SignalRelay& operator=(const SignalRelay&) = delete;
  ~SignalRelay() {
    if (m_type == nullptr) return;
    py::gil_scoped_acquire gil;  // never raised (another exception won): drop the references
    Py_XDECREF(m_type);
    Py_XDECREF(m_value);
    Py_XDECREF(m_traceback);
  }

  bool poll() {
    const auto now = std::chrono::steady_clock::now();
    if (now - m_last < std::chrono::milliseconds(20)) return false;
    m_last = now;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() == 0) return false;
    PyErr_Fetch(&m_type, &m_value, &m_traceback);
    return true;
  }

  /// With the GIL held: raise the handler's exception (KeyboardInterrupt if it left none).
  [[noreturn]] void raise() {
    if (m_type != nullptr) {
      PyErr_Restore(m_type, m_value, m_traceback);
      m_type = m_value = m_traceback = nullptr;
    } else {
      PyErr_SetNone(PyExc_KeyboardInterrupt);
    }
    throw py::error_already_set();
  }

 private:
  std::chrono::steady_clock::time_point m_last{};
  PyObject* m_type = nullptr;
  PyObject* m_value = nullptr;
  PyObject* m_traceback = nullptr;
};

// Python's logging level of the "hemicontact" logger decides which lines the library formats at
// all: below the logger's level they cost nothing (and take no GIL). A program that never imported
// logging has configured nothing: WARNING, Python's default, without importing logging (~10 ms of
// a short script's run; the sink imports it for the first warning).
void sync_log_level() {
  int level = 30;
  if (py::module_::import("sys").attr("modules").contains("logging"))
    level = py::module_::import("logging").attr("getLogger")("hemicontact").attr("getEffectiveLevel")().cast<int>();
  set_log_level(level <= 10 ? LogLevel::DEBUG : level <= 20 ? LogLevel::INFO : level <= 30 ? LogLevel::WARN : LogLevel::QUIET);
}

// While more than one solve runs in this process, OpenBLAS runs each call on the calling thread.
// Each solve's factorizations call the BLAS, and OpenBLAS's own threads (2 by default on 2 cores)
// from two solves at once spin against each other: fig2 n = 128 in ThreadPoolExecutor(2) took
// 0.5 s of CPU per solve instead of 0.15 s, slower than one after the other; with one BLAS thread
// per call, eight random scenes took 0.68x their serial time (docs/python.md). A single solve keeps
// the BLAS as configured (the CLI's settings); the count is restored once no solve runs, and an
// OPENBLAS_NUM_THREADS in the environment is left alone. Looked up at run time, as the adaptive
// loop does: a build against another BLAS has no such function.
class ConcurrentSolves {
 public:
  ConcurrentSolves() {
    const std::lock_guard<std::mutex> lock(mutex());
    State& st = state();
    // Each solve running at once may be inside a BLAS call, each needing its own OpenBLAS buffer:
    // mapped here while it fits, or this solve ends with the memory error (OpenBLAS would retry a
    // failed mapping for ever: two solves under ulimit -v hung).
    reserve_blas_buffers(st.active + 1);
    if (++st.active == 2 && st.set != nullptr && st.get != nullptr) {
      const int n = st.get();
      if (n > 1) {
        st.saved = n;
        st.set(1);
      }
    }
  }
  ~ConcurrentSolves() {
    const std::lock_guard<std::mutex> lock(mutex());
    State& st = state();
    if (--st.active == 0 && st.saved > 1) {
      st.set(st.saved);
      st.saved = 0;
    }
  }
  ConcurrentSolves(const ConcurrentSolves&) = delete;
  ConcurrentSolves& operator=(const ConcurrentSolves&) = delete;

 private:
  struct State {
    int active = 0;
    int saved = 0;  // the thread count to restore (0: nothing changed)
    int (*get)() = nullptr;
    void (*set)(int) = nullptr;
    State() {
      if (std::getenv("OPENBLAS_NUM_THREADS")) return;
      get = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
      set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
    }
  };
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  static State& state() {
    static State s;
    return s;
  }
};

// Run @p f without the GIL, interruptible by Ctrl-C when called on the main thread.
template <class F>
auto run_released(F&& f) -> decltype(f()) {
  sync_log_level();
  SignalRelay relay;
  std::optional<ScopedInterruptCheck> check;
  // Python runs signal handlers on the main thread only: other threads need no check.
  if (PyThread_get_thread_ident() == g_main_thread) check.emplace([&relay] { return relay.poll(); });
  try {
    py::gil_scoped_release nogil;
    const ConcurrentSolves counted;
    return f();
  } catch (const Interrupted&) {
    relay.raise();  // the GIL is held again: nogil ended with the try block
  }
}

// ------------------------------------------------------------------ scenes
// A scene as the CLI sees it: a file (or a dict's JSON text) and the --set assignments applied to
// it in order, validated as a whole after each change, so that messages are the CLI's.
struct Scene {
  std::optional<std::string> path;  // the scene file, or none for a dict
  std::string text;                 // the dict's JSON text (no file)
  std::string directory;            // relative paths in the scene (mesh.file) are taken from here
  std::vector<std::string> overrides;
  json effective;  // validated, every default injected

  json load(const std::vector<std::string>& ov) const {
    return path ? load_scene(*path, ov) : load_scene_text(text, "<dict>", ov);
  }

  static Scene from_file(const std::string& p) {
    Scene s;
    s.path = p;
    s.directory = scene_directory(p);
    s.effective = s.load({});
    return s;
  }

  static Scene from_dict(py::handle dict, const std::string& directory) {
    Scene s;
    s.text = py_json_dumps(dict);
    s.directory = directory;
    s.effective = s.load({});
    return s;
  }

  // Apply CLI-style assignments ("mesh.n=128"); on an error the scene is unchanged.
  void apply(const std::vector<std::string>& assignments) {
    std::vector<std::string> ov = overrides;
    ov.insert(ov.end(), assignments.begin(), assignments.end());
    json e = load(ov);
    overrides = std::move(ov);
    effective = std::move(e);
  }

  // The effective scene with @p extra assignments applied (the scene itself is unchanged).
  json with(const std::vector<std::string>& extra) const {
    if (extra.empty()) return effective;
    std::vector<std::string> ov = overrides;
    ov.insert(ov.end(), extra.begin(), extra.end());
    return load(ov);
  }

  std::string name() const { return path ? *path : std::string("<dict>"); }
};

std::string assignment(const std::string& key, py::handle value) { return key + "=" + py_json_dumps(value); }

// The engine a call of the module runs (solver/engine_choice.hpp): solve and converge take what
// `hemicontact solve` would (the petsc engine as a process of its own, studies/petsc_process.hpp);
// path, which restarts one solver from many points, runs the cholmod engine (a given petsc is
// refused) and says where `hemicontact solve` would have taken the petsc engine; minima decides
// as the CLI does (minima_engine, in minima_study).
EngineChoice module_engine(const json& scene, const std::string& directory, const char* what, int reference = 0) {
  const std::string w = what;
  const bool hands_over = w == "solve" || w == "converge";
  if (!hands_over && scene.at("solver").at("engine").get<std::string>() == "petsc")
    input_error(w + ": solver.engine = petsc solves one scene from zero (`hemicontact solve`, the module's solve "
                    "and converge); " + w + " restarts one solver from many points: use solver.engine = cholmod");
  if (const std::string missing = petsc_engine_missing();
      hands_over && !missing.empty() && scene.at("solver").at("engine").get<std::string>() == "petsc")
    input_error(w + ": solver.engine = petsc: " + missing);
  EngineChoice e = reference > 0 ? convergence_engine(scene, directory, reference, petsc_engine_available())
                   : hands_over  ? choose_engine(scene, directory, petsc_engine_available(), adapt_requested(scene))
                                 : in_process_engine(scene, directory, petsc_engine_available(), "the Python module's " + w);
  log_engine_choice(e);
  return e;
}

// ------------------------------------------------------------------ results
// One solve's model, solution and what its report needs; shared by the Result and, for minima,
// by each distinct solution's Result (one model).
struct Solved : SceneSolve {
  std::optional<json> report_cache;

  const json& report() {
    if (!report_cache) report_cache = scene_solve_report(*this);
    return *report_cache;
  }
};

// A copy into an array that NumPy owns.
py::array_t<double> matrix(const double* data, Index rows, Index cols) {
  py::array_t<double> a({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
  std::copy(data, data + rows * cols, a.mutable_data());
  return a;
}

py::array_t<double> vector(const Vec& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.data(), v.data() + v.size(), a.mutable_data());
  return a;
}

py::array_t<std::int64_t> int_matrix(const IMat& m) {
  py::array_t<std::int64_t> a({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  std::copy(m.data(), m.data() + m.size(), a.mutable_data());
  return a;
}

std::shared_ptr<Solved> py_solve(const Scene& s, const std::vector<std::string>& extra) {
  const json scene = s.with(extra);
  const EngineChoice engine = module_engine(scene, s.directory, "solve");
  (void)solve_options_from_scene(scene);  // its input errors before the GIL is released
  return run_released([&] {
    auto out = std::make_shared<Solved>();
    // As `hemicontact solve` (studies/scene_solve.hpp); with adapt.target_error the final mesh's
    // model and solution, the loop's history in the report.
    if (engine.engine == "petsc") {
      refuse_adaptive_outside_cholmod(scene);
      const PetscProcess petsc(scene, s.directory);
      static_cast<SceneSolve&>(*out) = solve_scene_with(scene, s.directory, petsc);
      out->extra["petsc"] = petsc.last_report().at("petsc");
    } else {
      static_cast<SceneSolve&>(*out) = solve_scene(scene, s.directory);
    }
    out->extra["engine_choice"] = engine_choice_json(engine);
    if (!out->missed.empty()) log_warn() << out->missed;
    return out;
  });
}

// Result.write(folder): the files `hemicontact solve --out folder` writes (the pictures apart).
void write_result(Solved& r, const std::string& folder, bool force) {
  const json report = r.report();
  run_released([&] {
    // The writers keep the folder being written in process-wide state (output/output_dir.hpp: one
    // --out folder per process, its handle and the interrupt message): one write at a time.
    static std::mutex write_mutex;
    const std::lock_guard<std::mutex> serial(write_mutex);
    const OutputLock lock = prepare_output_dir(folder, force, solve_output_names());
    write_scene_solve(folder, r, report);
    return 0;
  });
}

py::dict gamma3_arrays(const Solved& r) {
  const Model& md = *r.model;
  const ContactState& st = r.solution.state;
  py::array_t<std::int64_t> nodes(static_cast<py::ssize_t>(md.contact.node.size()));
  std::copy(md.contact.node.begin(), md.contact.node.end(), nodes.mutable_data());
  RowMat x(md.contact.size(), md.dim());
  for (Index k = 0; k < md.contact.size(); ++k) x.row(k) = md.mesh.points.row(md.contact.node[static_cast<size_t>(k)]);
  py::dict d;
  d["node"] = nodes;
  d["x"] = matrix(x.data(), x.rows(), x.cols());
  d["normal"] = matrix(md.contact.normal.data(), md.contact.normal.rows(), md.contact.normal.cols());
  d["w"] = vector(md.contact.w);
  d["g"] = vector(md.contact.g);
  d["u_nu"] = vector(st.u_nu);
  d["u_tau"] = vector(st.u_tau);
  d["sigma_nu"] = vector(st.sigma_nu);
  d["sigma_tau"] = vector(st.sigma_tau);
  d["xi"] = vector(st.xi);
  d["lambda"] = vector(st.lambda);
  return d;
}

// The strain, stress and von Mises stress per cell: the VTU writer's own computation
// (output/vtk_writer.hpp), not a copy of it.
py::dict cell_field_arrays(const Solved& r) {
  const CellFields f = cell_fields(*r.model, r.solution);
  py::dict d;
  d["strain"] = matrix(f.strain.data(), f.strain.rows(), f.strain.cols());
  d["stress"] = matrix(f.stress.data(), f.stress.rows(), f.stress.cols());
  d["von_mises"] = vector(f.von_mises);
  return d;
}

// The CLI's ranges of the study options (problem/minima_report.hpp, studies/convergence.hpp), for
// the keywords' checks in __init__.py: one home for each limit.
py::dict option_limits() {
  py::dict limits;
  limits["starts"] = MINIMA_MAX_STARTS;
  limits["load_path_steps"] = MINIMA_MAX_LOAD_PATH_STEPS;
  limits["seed"] = MINIMA_MAX_SEED;
  limits["level"] = MAX_LEVEL;  // converge's levels and reference
  limits["path_steps"] = PATH_MAX_STEPS;
  return limits;
}

py::dict certificate_dict(const CertificateReport& c) {
  py::dict residuals;
  for (const auto& r : c.residuals) residuals[py::str(r.name)] = r.value;
  py::dict d;
  d["passed"] = c.passed;
  d["max_residual"] = c.max_residual;
  d["tol"] = c.tol;
  d["residuals"] = residuals;
  return d;
}

// ------------------------------------------------------------------ studies
// A study's solutions as Results of one model (minima's distinct solutions, path's states).
template <class Item, class Get>
std::vector<std::shared_ptr<Solved>> results_of(const std::shared_ptr<const Model>& md, const SolveOptions& opt,
                                                const json& scene, const std::vector<Item>& items, Get solution_of) {
  std::vector<std::shared_ptr<Solved>> out;
  for (const Item& item : items) {
    auto one = std::make_shared<Solved>();
    one->model = md;
    one->solution = solution_of(item);
    one->opt = opt;
    one->scene = scene;
    out.push_back(std::move(one));
  }
  return out;
}

// A study's dict as the CLI's file has it (the scene file's name and the effective scene added),
// and its Results under @p key.
py::dict study_dict(json js, const Scene& s, const json& scene, const char* key,
                    const std::vector<std::shared_ptr<Solved>>& results) {
  js["name"] = s.path ? std::filesystem::path(*s.path).stem().string() : std::string("dict");
  js["scene_file"] = s.name();
  js["scene"] = scene;
  py::dict out;
  out["report"] = to_py(js);
  out[key] = py::cast(results);
  return out;
}

py::object minima_study(const Scene& s, const std::vector<std::string>& extra, MinimaOptions mo, bool barriers) {
  const json scene = s.with(extra);
  // The CLI's rule (minima_engine): the petsc engine for a large 3D mesh, every start judged here.
  const EngineChoice engine = minima_engine(scene, s.directory, petsc_engine_available(), !mo.backends.empty(), barriers);
  log_engine_choice(engine);
  const SolveOptions opt = solve_options_from_scene(scene);
  if (engine.engine == "petsc") petsc_minima_starts(scene, s.directory, opt, mo);
  auto [js, solved] = run_released([&] {
    auto md = std::make_shared<const Model>(build_model(scene, s.directory));
    if (barriers) require_barrier_scene(*md);  // before the search, as the CLI
    const MinimaReport r = find_minima(*md, opt, mo);
    json j = minima_json(*md, r);
    j["unseen"] = unseen_json(r.unseen, r.options);
    j["engine_choice"] = engine_choice_json(engine);
    if (barriers) {
      j["barriers"] = json::array();
      for (const Barrier& b : find_barriers(*md, opt, r, BarrierOptions{})) j["barriers"].push_back(barrier_json(b));
    }
    auto sols = results_of(md, opt, scene, r.solutions, [](const DistinctSolution& d) { return d.solution; });
    return std::make_pair(std::move(j), std::move(sols));
  });
  return study_dict(std::move(js), s, scene, "solutions", solved);
}

// `hemicontact path` without its files: path.json's dict and each state's Result.
py::object path_study(const Scene& s, const std::vector<std::string>& extra, const PathOptions& po) {
  const json scene = s.with(extra);
  const EngineChoice engine = module_engine(scene, s.directory, "path");
  const SolveOptions opt = solve_options_from_scene(scene);
  auto [js, states] = run_released([&] {
    auto md = std::make_shared<const Model>(build_model(scene, s.directory));
    const PathReport R = follow_load_path(*md, opt, po);
    json j = path_json(*md, R);
    j["engine_choice"] = engine_choice_json(engine);
    auto sols = results_of(md, opt, scene, R.states, [](const PathState& st) { return st.solution; });
    return std::make_pair(std::move(j), std::move(sols));
  });
  return study_dict(std::move(js), s, scene, "states", states);
}

py::object convergence_study(const Scene& s, const std::vector<std::string>& extra, const std::vector<int>& levels,
                             int reference) {
  const json scene = s.with(extra);
  const EngineChoice engine = module_engine(scene, s.directory, "converge", reference);
  json js = run_released(
      [&] { return convergence_json(run_convergence(scene, s.directory, levels, reference, nullptr, petsc_engine_available())); });
  js["engine_choice"] = engine_choice_json(engine);
  js["name"] = s.path ? std::filesystem::path(*s.path).stem().string() : std::string("dict");
  js["scene_file"] = s.name();
  return to_py(js);
}

}  // namespace
}  // namespace hemicontact::python

PYBIND11_MODULE(_hemicontact, m) {
  using namespace hemicontact;
  using namespace hemicontact::python;
  m.doc() = "hemicontact's compiled core; use the package `hemicontact` (its __init__ documents the API).";

  g_main_thread = PyThread_get_thread_ident();
  configure_process_for_solves();

  // Errors: a bad scene, key, value or other input (the CLI's exit codes 1 and 2) is SceneError,
  // a ValueError, with the CLI's message; anything else is HemicontactError (a RuntimeError).
  static py::exception<Error> scene_error(m, "SceneError", PyExc_ValueError);
  static py::exception<std::runtime_error> other_error(m, "HemicontactError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      if (e.code() == EXIT_INPUT || e.code() == EXIT_USAGE)
        scene_error(e.what());
      else
        other_error(e.what());
    }
  });

  // Log lines to logging.getLogger("hemicontact") (until the interpreter exits: then stderr
  // again, since no Python code can run).
  // The logger is looked up at the first line (importing logging costs a short script ~10 ms);
  // leaked on purpose: no Python object may be released after the interpreter is gone.
  static py::object* logger = nullptr;
  set_log_sink([](LogLevel level, const std::string& line) {
    py::gil_scoped_acquire gil;
    const int pylevel = level == LogLevel::DEBUG ? 10 : level == LogLevel::INFO ? 20 : 30;
    try {
      if (logger == nullptr) logger = new py::object(py::module_::import("logging").attr("getLogger")("hemicontact"));
      logger->attr("log")(pylevel, line);
    } catch (py::error_already_set& e) {
      e.discard_as_unraisable("hemicontact log line");
    }
  });
  py::module_::import("atexit").attr("register")(py::cpp_function([] { set_log_sink(nullptr); }));

  py::class_<Scene>(m, "_Scene")
      .def_static("load", &Scene::from_file, py::arg("path"))
      .def_static("from_dict", &Scene::from_dict, py::arg("scene"), py::arg("directory"))
      .def("apply", &Scene::apply, py::arg("assignments"))
      .def("set", [](Scene& s, const std::string& key, py::handle value) { s.apply({assignment(key, value)}); })
      .def("get",
           [](const Scene& s, const std::string& key) -> py::object {
             try {
               return to_py(scene_at(s.effective, key));
             } catch (const Error&) {
               throw py::key_error(key);
             }
           })
      .def("effective", [](const Scene& s) { return to_py(s.effective); })
      .def("with_assignments", [](const Scene& s, const std::vector<std::string>& extra) { return to_py(s.with(extra)); })
      .def("copy", [](const Scene& s) { return Scene(s); })
      .def_property_readonly("path", [](const Scene& s) { return s.path; })
      .def_property_readonly("directory", [](const Scene& s) { return s.directory; })
      .def_property_readonly("overrides", [](const Scene& s) { return s.overrides; });

  py::class_<Solved, std::shared_ptr<Solved>>(m, "_Solved")
      .def_property_readonly("energy", [](const Solved& r) { return r.solution.energy; })
      .def_property_readonly("energy_norm", [](const Solved& r) { return r.solution.energy_norm; })
      .def_property_readonly("ok", [](Solved& r) { return r.report().value("ok", false); })
      .def_property_readonly("message", [](Solved& r) { return r.report().value("message", std::string()); })
      .def_property_readonly("solved_by", [](const Solved& r) { return r.solution.solved_by(); })
      .def_property_readonly("dim", [](const Solved& r) { return r.model->dim(); })
      .def_property_readonly("certificate", [](const Solved& r) { return certificate_dict(r.solution.certificate); })
      .def_property_readonly("statuses",
                             [](const Solved& r) {
                               std::vector<std::string> s;
                               for (const NodeStatus& n : r.solution.status) s.push_back(n.str());
                               return s;
                             })
      .def_property_readonly("status_counts", [](const Solved& r) { return r.solution.status_counts(); })
      .def_property_readonly("points",
                             [](const Solved& r) {
                               const RowMat& p = r.model->mesh.points;
                               return matrix(p.data(), p.rows(), p.cols());
                             })
      .def_property_readonly("cells", [](const Solved& r) { return int_matrix(r.model->mesh.cells); })
      .def_property_readonly("u",
                             [](const Solved& r) {
                               const Index d = r.model->dim();
                               return matrix(r.solution.u.data(), r.solution.u.size() / d, d);
                             })
      .def_property_readonly("gamma3", &gamma3_arrays)
      .def_property_readonly("cell_fields", &cell_field_arrays)
      .def_property_readonly("timings", [](const Solved& r) { return r.solution.timings; })
      .def_property_readonly("scene", [](const Solved& r) { return to_py(r.scene); })
      .def("report", [](Solved& r) { return to_py(r.report()); })
      .def("summary", [](const Solved& r) { return summary_table(*r.model, r.solution); })
      .def("write", &write_result, py::arg("folder"), py::arg("force") = false);

  m.def("solve", &py_solve, py::arg("scene"), py::arg("assignments"));
  m.def(
      "minima",
      [](const Scene& s, const std::vector<std::string>& extra, int starts, unsigned seed,
         const std::vector<std::string>& backends, double group_tol, double box, int load_path_steps,
         const std::vector<Vec>& user_starts, bool barriers, bool until_complete, int max_starts) {
        MinimaOptions mo;
        mo.starts = starts;
        mo.seed = seed;
        mo.backends = backends;
        mo.group_tol = group_tol;
        mo.box = box;
        mo.load_path_steps = load_path_steps;
        mo.user_starts = user_starts;
        mo.until_complete = until_complete;
        mo.max_starts = max_starts;
        return minima_study(s, extra, mo, barriers);
      },
      py::arg("scene"), py::arg("assignments"), py::arg("starts"), py::arg("seed"), py::arg("backends"),
      py::arg("group_tol"), py::arg("box"), py::arg("load_path_steps"), py::arg("user_starts"), py::arg("barriers"),
      py::arg("until_complete"), py::arg("max_starts"));
  m.def(
      "path",
      [](const Scene& s, const std::vector<std::string>& extra, const std::vector<double>& loads, int steps,
         double bisection_tol) {
        PathOptions po;
        po.loads = loads;
        po.steps = steps;
        po.bisection_tol = bisection_tol;
        return path_study(s, extra, po);
      },
      py::arg("scene"), py::arg("assignments"), py::arg("loads"), py::arg("steps"), py::arg("bisection_tol"));
  m.def("converge", &convergence_study, py::arg("scene"), py::arg("assignments"), py::arg("levels"),
        py::arg("reference"));
  m.def("parse_levels", &parse_levels, py::arg("text"));
  m.def("backends", [] {
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& [name, doc] : available_backends()) out.emplace_back(name, doc);
    return out;
  });
  m.def(
      "random_scene_assignments",
      [](unsigned seed, int n_min, int n_max) { return stress::draw_default_scene(seed, n_min, n_max).overrides; },
      py::arg("seed"), py::arg("n_min"), py::arg("n_max"));
  m.attr("limits") = option_limits();
  m.attr("__version__") = HEMICONTACT_VERSION;
}
