// The house as drawn (docs/architecture.md): folders form layers and every `#include <hemicontact/X/...>`
// points down (or within its own folder), so the folder-level include graph has no cycle.
//
//   core, config                                   0  types, errors, logging
//   mesh, material, nlp                            1  geometry; the law F; the abstract NLP + backends
//   contact                                        2  Γ3 nodes, p_ν, F_b, smoothing (reads mesh)
//   fem                                            3  P1 kernels, assembly (linear and nonlinear), dofs, CHOLMOD
//   energy                                         4  the terms of Π_λ (reads fem, contact, nlp)
//   problem                                        5  Model, Solution and the result records every stage passes on
//   check                                          6  contact state, statuses, certificate, (21)
//   scene                                          7  scene input: schema, validation, building the Model
//   output                                         7  writers: report.json, VTU, CSV, study tables (read problem/'s records)
//   solver                                         8  ContactSolver (backend stages, fixed point, exact solver, polish), adaptive solve
//   studies                                        9  what solves a scene many times: convergence, minima, work-precision
//   cli                                            10 the program
//   petsc                                          11 the petsc engine's program (hemicontact-mpi; reads cli)
//
// output/ sits beside scene/, below the solver: a writer formats the records problem/ holds (the
// studies' results included) and never includes the code that computes them. The adaptive solve is
// in solver/, below studies/, because the adaptive work-precision study runs it.
//
// The test reads the sources, so it fails the moment an include climbs a layer.
//
// The house also stands alone: no file in it points at files a clone does not have (a folder beside
// the repository, documents kept elsewhere) or at an issue tracker its reader cannot see; a comment
// says the reason itself. House.NothingPointsOutsideTheRepository reads every text file of the tree.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const std::map<std::string, int> LAYER = {{"core", 0},    {"config", 0}, {"mesh", 1},   {"material", 1}, {"nlp", 1},
                                          {"contact", 2}, {"fem", 3},    {"energy", 4}, {"problem", 5},  {"check", 6},
                                          {"scene", 7},   {"output", 7}, {"solver", 8}, {"studies", 9},
                                          {"cli", 10},    {"petsc", 11}};

struct Edge {
  std::string from, to, file;
};

/// Folder of a source path below include/hemicontact/ or src/ ("config" for config.hpp.in).
std::string folder_of(const fs::path& rel) {
  const std::string first = rel.begin()->string();
  return rel.has_parent_path() ? first : "config";
}

std::vector<Edge> include_edges() {
  const fs::path root(HEMICONTACT_SOURCE_DIR);
  const std::regex inc(R"(^\s*#\s*include\s*<hemicontact/([a-z_]+)(/|\.hpp>))");
  std::vector<Edge> edges;
  for (const fs::path& base : {root / "include" / "hemicontact", root / "src"})
    for (const auto& e : fs::recursive_directory_iterator(base)) {
      if (!e.is_regular_file()) continue;
      const std::string ext = e.path().extension().string();
      if (ext != ".hpp" && ext != ".cpp" && ext != ".in") continue;
      const std::string from = folder_of(fs::relative(e.path(), base));
      std::ifstream in(e.path());
      std::string line;
      std::smatch m;
      while (std::getline(in, line))
        if (std::regex_search(line, m, inc)) {
          const std::string to = m[2] == "/" ? m[1].str() : "config";
          edges.push_back({from, to, fs::relative(e.path(), root).string()});
        }
    }
  return edges;
}

}  // namespace

TEST(House, EveryFolderHasALayer) {
  const fs::path root(HEMICONTACT_SOURCE_DIR);
  std::set<std::string> unknown;
  for (const fs::path& base : {root / "include" / "hemicontact", root / "src"})
    for (const auto& e : fs::directory_iterator(base))
      if (e.is_directory() && !LAYER.count(e.path().filename().string())) unknown.insert(e.path().filename().string());
  for (const auto& f : unknown) ADD_FAILURE() << "folder '" << f << "' has no layer in the table above";
}

TEST(House, IncludesPointDownOnly) {
  const std::vector<Edge> edges = include_edges();
  ASSERT_GT(edges.size(), 100u);  // the sources were found
  for (const Edge& e : edges) {
    ASSERT_TRUE(LAYER.count(e.from)) << e.file;
    ASSERT_TRUE(LAYER.count(e.to)) << e.file << " includes unknown folder " << e.to;
    if (e.from == e.to) continue;
    EXPECT_LT(LAYER.at(e.to), LAYER.at(e.from)) << e.file << ": " << e.from << " (layer " << LAYER.at(e.from)
                                                << ") includes " << e.to << " (layer " << LAYER.at(e.to) << ")";
  }
}

// Implied by the layers, and the property the house needs: no folder reaches itself.
TEST(House, FolderGraphHasNoCycle) {
  std::map<std::string, std::set<std::string>> out;
  for (const Edge& e : include_edges())
    if (e.from != e.to) out[e.from].insert(e.to);
  std::map<std::string, int> state;  // 0 new, 1 on the stack, 2 done
  std::vector<std::string> stack;
  std::string cycle;
  std::function<void(const std::string&)> visit = [&](const std::string& v) {
    state[v] = 1;
    stack.push_back(v);
    for (const auto& w : out[v]) {
      if (!cycle.empty()) return;
      if (state[w] == 1) {
        std::ostringstream os;
        for (auto it = std::find(stack.begin(), stack.end(), w); it != stack.end(); ++it) os << *it << " -> ";
        cycle = os.str() + w;
      } else if (state[w] == 0) {
        visit(w);
      }
    }
    stack.pop_back();
    state[v] = 2;
  };
  for (const auto& [v, _] : out)
    if (state[v] == 0) visit(v);
  EXPECT_TRUE(cycle.empty()) << "include cycle: " << cycle;
}

namespace {

/// What the repository holds: its folders and the files at its top, as git tracks them. Build
/// folders, caches and editor files (.gitignore) are left out, and so are binary files (a NUL byte:
/// the pictures). @return the files, sorted, as paths relative to @p root.
std::vector<fs::path> standalone_repository_files(const fs::path& root) {
  const std::set<std::string> folders = {"src",     "include",  "tests", "bench", "fuzz",
                                         "scripts", "problems", "docs",  "cmake", ".ci"};
  const auto ignored = [](const fs::path& p) {
    const std::string name = p.filename().string();
    return name == "__pycache__" || p.extension() == ".swp";
  };
  std::vector<fs::path> files;
  for (const auto& top : fs::directory_iterator(root)) {
    const std::string name = top.path().filename().string();
    if (top.is_regular_file() && name != ".git" && !ignored(top.path())) {
      files.push_back(top.path());
    } else if (top.is_directory() && folders.count(name)) {
      for (auto it = fs::recursive_directory_iterator(top.path()); it != fs::recursive_directory_iterator(); ++it) {
        if (ignored(it->path())) {
          if (it->is_directory()) it.disable_recursion_pending();
          continue;
        }
        if (it->is_regular_file()) files.push_back(it->path());
      }
    }
  }
  std::vector<fs::path> text;
  for (const fs::path& f : files) {
    std::ifstream in(f, std::ios::binary);
    const std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (content.find('\0') == std::string::npos) text.push_back(fs::relative(f, root));
  }
  std::sort(text.begin(), text.end());
  return text;
}

}  // namespace

// A clone has only what is in the repository: no path may lead out of it (the shared folder beside
// the working copy, its documents and data), no citation may name a document that lives there (the
// model and the style guide the repository restates in docs/), and no comment may send its reader to
// a tracker's issue number instead of saying the reason. Each pattern is written in two pieces so
// that this file does not match itself.
TEST(House, NothingPointsOutsideTheRepository) {
  const fs::path root(HEMICONTACT_SOURCE_DIR);
  const std::vector<std::string> pieces = {std::string("shared/") + "docs", std::string("shared/") + "data",
                                           std::string("../") + "shared", std::string("MODEL") + ".md",
                                           std::string("STYLE") + ".md"};
  const std::regex tracker(std::string(R"(\b[Ii]ssues? #?)") + "[0-9]+");
  const std::vector<fs::path> files = standalone_repository_files(root);
  ASSERT_GT(files.size(), 200u);  // the tree was found
  for (const fs::path& rel : files) {
    std::ifstream in(root / rel);
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
      std::string found;
      for (const std::string& p : pieces)
        if (line.find(p) != std::string::npos) found = "'" + p + "'";
      std::smatch m;
      if (found.empty() && std::regex_search(line, m, tracker)) found = "tracker reference '" + m.str() + "'";
      if (!found.empty())
        ADD_FAILURE() << rel.string() << ":" << n << ": " << found
                      << " points outside the repository: " << line.substr(0, 160);
    }
  }
}

// What ships (the library's headers and sources, the programs, the Python module) includes nothing
// from tests/ or bench/: a quoted include names a file beside the including one or under src/
// (a program's private headers), never a path climbing out with "../", so that a user's build of
// the library and programs does not depend on the test tree.
TEST(House, ShippedCodeIncludesNothingFromTheTestTree) {
  const fs::path root(HEMICONTACT_SOURCE_DIR);
  const std::regex quoted(R"re(^\s*#\s*include\s*"([^"]+)")re");
  int files = 0;
  for (const char* dir : {"include", "src", "python/src"})
    for (const auto& e : fs::recursive_directory_iterator(root / dir)) {
      const std::string ext = e.path().extension().string();
      if (!e.is_regular_file() || (ext != ".hpp" && ext != ".cpp" && ext != ".in")) continue;
      ++files;
      std::ifstream in(e.path());
      std::string line;
      std::smatch m;
      for (int n = 1; std::getline(in, line); ++n) {
        if (!std::regex_search(line, m, quoted)) continue;
        const std::string inc = m[1].str();
        const bool beside = fs::exists(e.path().parent_path() / inc), in_src = fs::exists(root / "src" / inc);
        if (inc.find("..") != std::string::npos || !(beside || in_src))
          ADD_FAILURE() << fs::relative(e.path(), root).string() << ":" << n << ": #include \"" << inc
                        << "\" is neither beside the file nor under src/ (shipped code must not reach tests/ or bench/)";
      }
    }
  EXPECT_GT(files, 100);  // the tree was found
}

// Every C++ source file has a basename of its own across src/, include/, tests/, bench/ and fuzz/
// (a header and its source, x.hpp and x.cpp, are one pair): a debugger's breakpoint, a compiler
// message or a profile names a file by its basename, and two minima.cpp are two guesses.
TEST(House, SourceBasenamesAreUnique) {
  const fs::path root(HEMICONTACT_SOURCE_DIR);
  std::map<std::string, std::vector<std::string>> by_name;  // basename with extension -> paths
  for (const char* dir : {"src", "include", "tests", "bench", "fuzz"}) {
    if (!fs::exists(root / dir)) continue;
    for (const auto& e : fs::recursive_directory_iterator(root / dir)) {
      const std::string ext = e.path().extension().string();
      if (!e.is_regular_file() || (ext != ".cpp" && ext != ".hpp")) continue;
      by_name[e.path().filename().string()].push_back(fs::relative(e.path(), root).string());
    }
  }
  ASSERT_GT(by_name.size(), 50u) << "the walk found too few sources under " << root;
  for (const auto& [name, paths] : by_name)
    if (paths.size() > 1) {
      std::string all;
      for (const std::string& p : paths) all += "\n  " + p;
      ADD_FAILURE() << name << " is the basename of " << paths.size() << " files:" << all;
    }
}

namespace {

/// One function definition found by long_function_scan: where it starts, its name and its length.
struct FunctionDefinition {
  std::string file;  ///< relative to the repository
  int line = 0;      ///< the first line of its signature
  int length = 0;    ///< lines from the signature's first line to the closing brace
  std::string name;  ///< as written before the parameter list, qualified ("Engine::polish")
};

/// A line's text without a trailing `// comment` (one after a blank), and without trailing blanks.
std::string function_scan_code(const std::string& line) {
  std::string s = line;
  const size_t c = s.find(" //");
  if (c != std::string::npos) s.erase(c);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  return s;
}

/// The definitions at namespace scope in one file, by the layout every file here has (clang-format,
/// namespaces not indented): a signature starts at column 0 (not a comment, preprocessor line or
/// closing brace, not a namespace, class, struct, enum or union) and runs to the first line that
/// ends with `{` (within 12 lines; one that ends with `;` first is a declaration); it has a
/// parameter list and no `=` before it (a variable initialized by a lambda or a braced list is not a
/// function); the body ends at the next `}` in column 0. Member functions defined inside a class
/// body are not seen (none here is long).
std::vector<FunctionDefinition> function_definitions(const fs::path& path, const std::string& rel) {
  std::vector<std::string> lines;
  {
    std::ifstream in(path);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
  }
  const std::regex not_a_function(R"(^(template\s*<.*?>\s*)?(namespace|struct|class|enum|union|extern)\b)");
  const std::regex name_before_paren(R"(([A-Za-z_~][A-Za-z0-9_:~]*(operator\S*)?)\s*$)");
  std::vector<FunctionDefinition> found;
  const size_t n = lines.size();
  for (size_t i = 0; i < n; ++i) {
    const std::string first = function_scan_code(lines[i]);
    if (first.empty() || std::isspace(static_cast<unsigned char>(first[0])) || first[0] == '#' || first[0] == '/' ||
        first[0] == '*' || first[0] == '}' || first.back() == ';' || first.back() == '}')
      continue;
    size_t j = i;
    while (j < n && j < i + 12) {
      const std::string code = function_scan_code(lines[j]);
      if (!code.empty() && (code.back() == '{' || code.back() == ';')) break;
      ++j;
    }
    if (j >= n || j == i + 12 || function_scan_code(lines[j]).back() == ';') continue;
    std::string signature;
    for (size_t k = i; k <= j; ++k) signature += function_scan_code(lines[k]) + " ";
    const size_t paren = signature.find('(');
    if (std::regex_search(signature, not_a_function) || paren == std::string::npos ||
        signature.substr(0, paren).find('=') != std::string::npos) {
      i = j;
      continue;
    }
    size_t end = j + 1;
    while (end < n && (lines[end].empty() || lines[end][0] != '}')) ++end;
    std::smatch m;
    const std::string before = signature.substr(0, paren);
    const std::string name = std::regex_search(before, m, name_before_paren) ? m[1].str() : before;
    found.push_back({rel, static_cast<int>(i + 1), static_cast<int>(end - i + 1), name});
    i = end;
  }
  return found;
}

/// Every function definition in src/, include/ and bench/.
std::vector<FunctionDefinition> all_function_definitions() {
  const fs::path root(HEMICONTACT_SOURCE_DIR);
  std::vector<FunctionDefinition> all;
  for (const char* dir : {"src", "include", "bench"})
    for (const auto& e : fs::recursive_directory_iterator(root / dir)) {
      const std::string ext = e.path().extension().string();
      if (!e.is_regular_file() || (ext != ".cpp" && ext != ".hpp")) continue;
      const std::vector<FunctionDefinition> f = function_definitions(e.path(), fs::relative(e.path(), root).string());
      all.insert(all.end(), f.begin(), f.end());
    }
  return all;
}

}  // namespace

// No function is longer than 100 lines (signature to closing brace): a long one is split into
// named steps. The exceptions are listed by file and name.
TEST(House, NoFunctionOver100Lines) {
  constexpr int MAX_LINES = 100;
  const std::set<std::pair<std::string, std::string>> allowed = {
      // A data table: one entry per scene key, nothing to split.
      {"src/scene/scene_schema.cpp", "build_scene_schema"},
  };
  const std::vector<FunctionDefinition> all = all_function_definitions();
  ASSERT_GT(all.size(), 500u) << "the scan found too few function definitions";
  std::set<std::pair<std::string, std::string>> still_long;
  for (const FunctionDefinition& f : all) {
    if (f.length <= MAX_LINES) continue;
    if (allowed.count({f.file, f.name})) {
      still_long.insert({f.file, f.name});
      continue;
    }
    ADD_FAILURE() << f.file << ":" << f.line << ": " << f.name << " is " << f.length << " lines (at most "
                  << MAX_LINES << "): split it into named steps";
  }
  for (const auto& [file, name] : allowed)
    if (!still_long.count({file, name}))
      ADD_FAILURE() << file << ": " << name << " is allowed over " << MAX_LINES
                    << " lines but is no longer (or is gone): remove it from the list";
}

// README.md is the manual (what it is, the two commands, using it, where the rest is), not a lab
// notebook: measurements and their history live in bench/README.md and docs/, one file a subject.
TEST(House, ReadmeIsAManualOfAtMost300Lines) {
  std::ifstream in(fs::path(HEMICONTACT_SOURCE_DIR) / "README.md");
  ASSERT_TRUE(in) << "README.md not found in " << HEMICONTACT_SOURCE_DIR;
  int lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  EXPECT_GT(lines, 50) << "README.md lost its content";
  EXPECT_LE(lines, 300) << "README.md has " << lines << " lines: move measurements and history to docs/";
}
