#pragma once
/// @file study_json.hpp  The JSON of the landscape studies, written once for every front end: the
/// CLI's path.json and minima.json, and the dicts the Python module returns.
#include <hemicontact/problem/minima_report.hpp>
#include <hemicontact/problem/model.hpp>
#include <hemicontact/studies/barriers.hpp>
#include <hemicontact/studies/load_path.hpp>
#include <hemicontact/studies/minima.hpp>

#include <nlohmann/json.hpp>

namespace hemicontact {

/// @return path.json's content: the options, the verdict, every state and every jump (with the
/// Γ3 nodes that switched, their statuses and u_ν before and after, and their coordinates).
nlohmann::json path_json(const Model& md, const PathReport& R);

/// @return one barrier of minima.json's "barriers": the pair and each side (its λ, verdict,
/// energies, the saddle's residual and negative eigenvalues, the string's energy profile).
nlohmann::json barrier_json(const Barrier& b);

/// @return minima.json's "unseen": the Chao1 estimate of the solutions the random starts missed,
/// with the options that set how many starts ran.
nlohmann::json unseen_json(const UnseenEstimate& e, const MinimaOptions& mo);

}  // namespace hemicontact
