// The study writers: the tables, JSON and CSV of `hemicontact converge` (studies/convergence.hpp)
// and `hemicontact minima` (studies/minima.hpp), beside the other writers (report.json, VTU, CSV)
// so that studies/ computes and output/ formats; they read the records in problem/ only.
#include <hemicontact/output/study_writers.hpp>

#include <hemicontact/check/contact_status.hpp>
#include <hemicontact/core/error.hpp>
#include <hemicontact/core/format.hpp>
#include <hemicontact/output/output_dir.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace hemicontact {
namespace {

using json = nlohmann::json;
const char* const STATUS_KEYS[] = {"separated", "compliance", "contact", "stick", "slip+", "slip-", "slip"};



// Shortest round-trip form for the CSV (as the other writers do).
std::string exact(double v) {
  if (!std::isfinite(v)) return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

nlohmann::json level_json(const ConvergenceLevel& l) {
  const auto finite_or_null = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  return {{"n", l.n},
          {"h", l.h},
          {"h_max", l.h_max},
          {"dofs", l.dofs},
          {"energy_norm", l.energy_norm},
          {"error", finite_or_null(l.error)},
          {"order", finite_or_null(l.order)},
          {"seconds", l.seconds},
          {"status_counts", l.status_counts},
          {"certificate_max_residual", finite_or_null(l.certificate_residual)},
          {"converged", l.converged},
          {"certified", l.certified},
          {"ok", l.ok},
          {"nested", l.nested},
          {"message", l.message},
          {"solved_by", l.solved_by},
          {"unique_in_doubt", l.unique_in_doubt},
          {"other_branch", l.other_branch.empty() ? nlohmann::json() : nlohmann::json(l.other_branch)}};
}

// The levels flagged as lying on another branch (left out of the rate fit).
std::vector<int> left_out(const ConvergenceStudy& study) {
  std::vector<int> n;
  for (const auto& l : study.levels)
    if (!l.other_branch.empty()) n.push_back(l.n);
  return n;
}

}  // namespace

nlohmann::json convergence_json(const ConvergenceStudy& study) {
  nlohmann::json levels = nlohmann::json::array();
  for (const auto& l : study.levels) levels.push_back(level_json(l));
  const RateFit fit = fit_rate(study);
  nlohmann::json rate = nullptr;
  if (fit.valid)
    rate = {{"alpha", fit.alpha},
            {"C", fit.C},
            {"levels_used", fit.levels_used},
            {"max_rel_residual", fit.max_rel_residual},
            {"left_out", left_out(study)},
            {"model", "error = C * sqrt(h^(2 alpha) - h_ref^(2 alpha))"}};
  return {{"reference", level_json(study.reference)},
          {"levels", levels},
          {"solved_by", study.backend},
          {"ok", study.ok()},
          {"failed", study.failed()},
          {"scene", study.scene},
          {"rate_fit", rate}};
}

void write_convergence_csv(const std::string& path, const ConvergenceStudy& study) {
  std::string out = "n,h,h_max,dofs,energy_norm,error,order,seconds";
  for (const char* k : STATUS_KEYS) out += std::string(",") + k;
  out += ",certificate_max_residual,converged,certified,ok\n";
  for (const auto& l : study.levels) {
    out += std::to_string(l.n);
    for (double v : {l.h, l.h_max}) out += "," + csv_number(v);
    out += "," + std::to_string(l.dofs);
    for (double v : {l.energy_norm, l.error, l.order, l.seconds}) out += "," + csv_number(v);
    for (const char* k : STATUS_KEYS) {
      const auto it = l.status_counts.find(k);
      out += "," + std::to_string(it == l.status_counts.end() ? 0 : it->second);
    }
    out += "," + csv_number(l.certificate_residual);
    for (bool b : {l.converged, l.certified, l.ok}) out += b ? ",1" : ",0";
    out += '\n';
  }
  write_text_file(path, out);
}

std::string convergence_table(const ConvergenceStudy& study) {
  std::string out;
  char line[256];
  const auto row = [&](const ConvergenceLevel& l, const char* role) {
    const auto& c = l.status_counts;
    const auto get = [&](const char* k) { return c.count(k) ? c.at(k) : 0; };
    char counts[64], order[32] = "-";
    std::snprintf(counts, sizeof counts, "%d/%d/%d", get("separated"), get("compliance"), get("contact"));
    if (std::isfinite(l.order)) std::snprintf(order, sizeof order, "%.3f", l.order);
    std::snprintf(line, sizeof line, "%6d %10.4g %8lld %12.6g %12.4e %7s %9.3f %13s %11.3e %s%s\n", l.n, l.h,
                  static_cast<long long>(l.dofs), l.energy_norm, l.error, order, l.seconds, counts,
                  l.certificate_residual, l.ok ? "ok" : (l.converged ? "NOT CERTIFIED" : "NOT CONVERGED"), role);
    out += line;
  };
  std::snprintf(line, sizeof line, "%6s %10s %8s %12s %12s %7s %9s %13s %11s %s\n", "n", "h", "dofs", "|u_h|_E",
                "rel.error", "order", "solve [s]", "sep/com/con", "certificate", "verdict");
  out += line;
  for (const auto& l : study.levels) row(l, "");
  row(study.reference, "  (reference)");
  const RateFit fit = fit_rate(study);
  if (fit.valid) {
    std::snprintf(line, sizeof line,
                  "reference-corrected rate (finest %d levels, error = C sqrt(h^2a - h_ref^2a)): a = %.3f, "
                  "C = %.3g, fit residual %.1f%%\n",
                  fit.levels_used, fit.alpha, fit.C, 100 * fit.max_rel_residual);
    out += line;
  }
  for (const auto& l : study.levels)
    if (!l.other_branch.empty()) out += "n = " + std::to_string(l.n) + ": " + l.other_branch + "\n";
  const auto failed = study.failed();
  if (failed.empty()) {
    out += "all " + std::to_string(study.levels.size() + 1) + " solves converged and certified (solved by " +
           study.backend + ")\n";
  } else {
    out += "FAILED at n =";
    for (size_t i = 0; i < failed.size(); ++i) out += (i ? ", " : " ") + std::to_string(failed[i]);
    out += "\n";
  }
  return out;
}

json minima_json(const Model& md, const MinimaReport& r) {
  json j;
  const MinimaOptions& o = r.options;
  j["options"] = {{"starts", o.starts},
                  {"seed", o.seed},
                  {"backends", o.backends},
                  {"group_tol", o.group_tol},
                  {"box", o.box},
                  {"load_path_steps", o.load_path_steps},
                  {"user_starts", o.user_starts.size()},
                  {"second_order_tol", o.second_order_tol}};
  const SmallnessReport& q = r.smallness;
  j["smallness"] = {{"computed", q.computed}, {"m_F", q.m_F},
                    {"L_Fb", q.L_Fb},         {"alpha_j", q.alpha_j},
                    {"lambda_1", q.lambda_1}, {"lambda_1nu", q.lambda_1nu},
                    {"lhs", q.lhs},           {"uniqueness_guaranteed", q.computed && q.holds}};
  j["x_scale"] = r.x_scale;
  j["norm_scale"] = r.norm_scale;
  j["seconds"] = r.seconds;
  j["local_minima"] = r.local_minima();
  j["certified_runs"] = r.certified_runs();
  j["runs"] = json::array();
  for (const auto& run : r.runs)
    j["runs"].push_back({{"start", run.start},
                         {"backend", run.backend},
                         {"solved_by", run.solved_by},
                         {"converged", run.converged},
                         {"certified", run.certified},
                         {"energy", run.energy},
                         {"certificate", run.certificate},
                         {"seconds", run.seconds},
                         {"solution", run.group},
                         {"message", run.message}});
  j["solutions"] = json::array();
  for (size_t k = 0; k < r.solutions.size(); ++k) {
    const DistinctSolution& ds = r.solutions[k];
    const Solution& s = ds.solution;
    const SecondOrderCheck& c = ds.second_order;
    json js = {
        {"index", k},
        {"energy", s.energy},
        {"energy_norm", s.energy_norm},
        {"type", c.verdict},
        {"second_order",
         {{"verdict", c.verdict},
          {"lambda_min", c.lambda_min},
          {"scale", c.scale},
          {"kept", c.kept},
          {"removed_contact", c.removed_contact},
          {"removed_stick", c.removed_stick},
          {"degenerate", c.degenerate},
          {"note", c.note}}},
        {"status_counts", s.status_counts()},
        {"certificate",
         {{"passed", s.certificate.passed}, {"max_residual", s.certificate.max_residual}, {"tol", s.certificate.tol}}},
        {"n_starts", ds.runs.size()},
        {"starts", ds.starts},
        {"backends", ds.backends},
        {"mirror_of", ds.mirror_of >= 0 ? json(ds.mirror_of) : json(nullptr)},
        {"spread", ds.spread},
        {"max_u_nu", s.max_u_nu}};
    json nodes = json::array();
    for (Index i = 0; i < md.contact.size(); ++i) {
      const auto p = md.mesh.points.row(md.contact.node[static_cast<size_t>(i)]);
      json n = {{"node", md.contact.node[static_cast<size_t>(i)]},
                {"x", p[0]},
                {"y", p[1]},
                {"g", md.contact.g[i]},
                {"u_nu", s.state.u_nu[i]},
                {"u_tau", s.state.u_tau[i]},
                {"sigma_nu", s.state.sigma_nu[i]},
                {"sigma_tau", s.state.sigma_tau[i]},
                {"xi", s.state.xi[i]},
                {"lambda", s.state.lambda[i]},
                {"status", s.status[static_cast<size_t>(i)].str()}};
      if (md.dim() == 3) n["z"] = p[2];
      nodes.push_back(n);
    }
    js["nodes"] = nodes;
    j["solutions"].push_back(js);
  }
  return j;
}

void write_minima_csv(const std::string& path, const MinimaReport& r) {
  std::ostringstream out;
  const std::vector<std::string> counts{"separated", "compliance", "contact", "stick", "slip+", "slip-", "slip"};
  out << "k,energy,energy_norm,type,lambda_min,certificate,n_starts,backends,starts";
  for (const auto& c : counts) out << ',' << c;
  out << '\n';
  for (size_t k = 0; k < r.solutions.size(); ++k) {
    const DistinctSolution& ds = r.solutions[k];
    std::string backends, starts;
    for (const auto& [b, n] : ds.backends) backends += (backends.empty() ? "" : " ") + b + ":" + std::to_string(n);
    for (int run : ds.runs) {
      const MinimaRun& m = r.runs[static_cast<size_t>(run)];
      starts +=
          (starts.empty() ? "" : " ") + (r.options.backends.size() > 1 ? m.backend + ":" : std::string()) + m.start;
    }
    out << k << ',' << exact(ds.solution.energy) << ',' << exact(ds.solution.energy_norm) << ','
        << ds.second_order.verdict << ',' << exact(ds.second_order.lambda_min) << ','
        << exact(ds.solution.certificate.max_residual) << ',' << ds.runs.size() << ",\"" << backends << "\",\""
        << starts << '"';
    const auto sc = ds.solution.status_counts();
    for (const auto& c : counts) out << ',' << (sc.count(c) ? sc.at(c) : 0);
    out << '\n';
  }
  write_text_file(path, out.str());
}

namespace {
// A CSV text field: quoted, its quotes doubled (a backend's name has commas: "ssn (semismooth
// Newton, CG + gamg, PETSc, 1 rank)").
std::string csv_text(std::string text) {
  for (size_t q = text.find('"'); q != std::string::npos; q = text.find('"', q + 2)) text.insert(q, 1, '"');
  return '"' + text + '"';
}
}  // namespace

void write_minima_runs_csv(const std::string& path, const std::vector<MinimaRun>& runs) {
  std::ostringstream out;
  out << "run,start,backend,solved_by,converged,certified,energy,certificate,seconds,message\n";
  for (size_t i = 0; i < runs.size(); ++i) {
    const MinimaRun& m = runs[i];
    out << i << ',' << m.start << ',' << csv_text(m.backend) << ',' << csv_text(m.solved_by) << ','
        << (m.converged ? 1 : 0) << ',' << (m.certified ? 1 : 0) << ',' << exact(m.energy) << ','
        << exact(m.certificate) << ',' << exact(m.seconds) << ',' << csv_text(m.message) << '\n';
  }
  write_text_file(path, out.str());
}

std::string minima_table(const MinimaReport& r) {
  std::ostringstream os;
  char line[512];
  std::snprintf(line, sizeof line, "%3s  %-16s %-12s %-13s %-11s %-9s %6s  %s\n", "k", "energy", "|u|_E", "type",
                "lambda_min", "cert", "starts", "statuses (normal | tangential)");
  os << line;
  const auto abbrev = [](const std::map<std::string, int>& sc) {
    std::string a, b;
    for (const char* k : {"separated", "compliance", "contact"})
      if (sc.count(k) && sc.at(k))
        a += (a.empty() ? "" : " ") + std::string(k).substr(0, 4) + " " + std::to_string(sc.at(k));
    for (const char* k : {"stick", "slip+", "slip-", "slip"})
      if (sc.count(k) && sc.at(k)) b += (b.empty() ? "" : " ") + std::string(k) + " " + std::to_string(sc.at(k));
    return a + " | " + b;
  };
  for (size_t k = 0; k < r.solutions.size(); ++k) {
    const DistinctSolution& ds = r.solutions[k];
    std::snprintf(line, sizeof line, "%3zu  %-16s %-12s %-13s %-11s %-9s %6zu  %s\n", k,
                  fmt(ds.solution.energy, 10).c_str(), fmt(ds.solution.energy_norm, 6).c_str(),
                  ds.second_order.verdict.c_str(), fmt(ds.second_order.lambda_min, 3).c_str(),
                  fmt(ds.solution.certificate.max_residual, 2).c_str(), ds.runs.size(),
                  abbrev(ds.solution.status_counts()).c_str());
    os << line;
    std::string starts, backends;
    const bool several = r.options.backends.size() > 1;
    for (int run : ds.runs) {
      const MinimaRun& m = r.runs[static_cast<size_t>(run)];
      starts += (starts.empty() ? "" : " ") + (several ? m.backend + ":" : std::string()) + m.start;
    }
    for (const auto& [b, n] : ds.backends) backends += (backends.empty() ? "" : ", ") + b + " " + std::to_string(n);
    os << "       reached by [" << backends << "] from: " << starts << '\n';
    if (ds.mirror_of >= 0)
      os << "       mirror image of solution " << ds.mirror_of << " (same energy, Gamma3 reflected): one pair\n";
    if (!ds.second_order.note.empty()) os << "       note: " << ds.second_order.note << '\n';
  }
  int failed = 0;
  for (const auto& run : r.runs)
    if (!run.certified) ++failed;
  int pairs = 0;
  for (const auto& ds : r.solutions) pairs += ds.mirror_of >= 0;
  os << r.solutions.size() << " distinct solution(s), " << r.local_minima() << " local minim"
     << (r.local_minima() == 1 ? "um" : "a");
  if (pairs > 0) os << " (" << pairs / 2 << " mirror pair" << (pairs > 2 ? "s" : "") << " among them)";
  os << "; " << r.certified_runs() << " of " << r.runs.size()
     << " runs certified";
  if (r.smallness.computed)
    os << "; (21): " << fmt(r.smallness.lhs, 4) << (r.smallness.holds ? " < " : " >= ")
       << "m_F = " << fmt(r.smallness.m_F, 4) << ", uniqueness guaranteed: " << (r.smallness.holds ? "yes" : "no");
  os << '\n';
  // Per backend: runs, converged (by the backend's own test), certified; then the uncertified
  // starts and the first verdict among them (cut), or the backend failures the certificate passed.
  for (const auto& b : r.options.backends) {
    std::string bad, first, first_failed;
    int n = 0, conv = 0, cert = 0;
    for (const auto& run : r.runs) {
      if (run.backend != b) continue;
      ++n;
      conv += run.converged;
      cert += run.certified;
      if (!run.certified) {
        bad += (bad.empty() ? "" : " ") + run.start;
        if (first.empty()) first = run.start + ": " + run.message;
      } else if (!run.converged && first_failed.empty()) {
        first_failed = run.start + ": " + run.message;
      }
    }
    os << "  " << b << ": " << n << " runs, " << conv << " converged, " << cert << " certified\n";
    const auto cut = [](std::string m) { return m.size() > 160 ? m.substr(0, 157) + "..." : m; };
    if (!bad.empty()) os << "    not certified: " << bad << "\n    first: " << cut(first) << '\n';
    if (!first_failed.empty()) os << "    backend failed but certified, e.g. " << cut(first_failed) << '\n';
  }
  return os.str();
}

}  // namespace hemicontact
