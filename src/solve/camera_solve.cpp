#include "solve/camera_solve.h"

#include <ceres/ceres.h>
#include <fmt/format.h>
#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "params/toml_parse.h"
#include "scene/camera_goals.h"
#include "scene/scene_loader.h"
#include "scene/toml_reader.h"
#include "solve/free_params.h"
#include "solve/goals.h"

namespace anamorph::solve {

namespace {

bool is_coin_key(const std::string& override_or_key) {
  return override_or_key.starts_with("camera.coin.") || override_or_key.starts_with("camera.coin=");
}

// The camera key of a free scalar ("camera.look_at" component 1: look_at, 1;
// "camera.coin.0.radius": coin 0's radius), none for a key of a list or net or an org/dir
// function's key (those are differentiated through rebuilt cameras) or a value another follows (a
// polynomial's fov).
std::optional<CameraKey> camera_key(const FreeValues& free, const FreeScalar& s) {
  const FreeValue& v = free.values[s.value];
  if (v.dims.size() > 1 || !v.key.starts_with("camera.")) return std::nullopt;
  for (const DerivedValue& d : free.derived)
    if (d.value == s.value) return std::nullopt;
  CameraKey k;
  std::string name = v.key.substr(7);
  if (name.starts_with("coin.")) {
    const size_t end = name.find('.', 5);
    if (end == std::string::npos) return std::nullopt;
    k.coin = std::stoi(name.substr(5, end - 5));
    name = name.substr(end + 1);
  }
  if (name.find('.') != std::string::npos) return std::nullopt;
  k.name = name;
  k.component = s.component;
  return k;
}

// Cameras at given free values, built by the scene reader from the text parsed once
// (ViewTemplate). The last few are kept: Ceres asks for each residual block at the same points in
// turn (the point and its 2n central differences), so each camera is built once per Jacobian, not
// once per block.
// The goals' tables, which the camera does not read (read again at every build, they would cost a
// tenth of it).
const std::vector<std::string> kGoalTables = {"camera.constraint", "camera.free", "camera.solve"};

class CameraBuilder {
 public:
  CameraBuilder(const SolveInput& in, const FreeValues& free, bool plain)
      : in_(in),
        free_(free),
        plain_(plain),
        capacity_(2 * free.scalars.size() + 2),
        view_(in.text, in.file, kGoalTables) {
    for (const FreeScalar& s : free.scalars) keys_.push_back(camera_key(free, s));
    std::vector<std::string> without = kGoalTables;
    without.emplace_back("camera.coin");
    if (plain) plain_view_.emplace(in.text, in.file, without);
  }

  // Null when the reader refuses the values (the solver then takes a shorter step). Valid until
  // 2n + 2 other values were asked for.
  const CameraPair* at(const double* x) { return hold(x).get(); }
  const std::vector<std::optional<CameraKey>>& keys() const { return keys_; }
  // The same, kept alive as long as the caller holds it.
  std::shared_ptr<const CameraPair> hold(const double* x) {
    const std::vector<double> xs(x, x + free_.scalars.size());
    for (const std::shared_ptr<Built>& b : cache_)
      if (b->x == xs) return pair_of(b);
    if (cache_.size() < capacity_) cache_.emplace_back();
    std::shared_ptr<Built>& b = cache_[next_];
    next_ = (next_ + 1) % capacity_;
    b = std::make_shared<Built>(build(xs));
    return pair_of(b);
  }

 private:
  struct Built {
    std::vector<double> x;
    bool ok = false;
    std::unique_ptr<Scene> camera, plain;
    CameraPair pair;
  };

  static std::shared_ptr<const CameraPair> pair_of(const std::shared_ptr<Built>& b) {
    return b->ok ? std::shared_ptr<const CameraPair>(b, &b->pair) : nullptr;
  }

  Built build(const std::vector<double>& xs) const {
    Built b;
    b.x = xs;
    try {
      std::vector<std::string> o = in_.overrides;
      for (std::string& s : free_.overrides(xs)) o.push_back(std::move(s));
      b.camera = std::make_unique<Scene>(view_.build(o, in_.frame, models()));
      b.pair = {b.camera->camera.get(), nullptr};
      if (plain_) {
        std::erase_if(o, is_coin_key);
        b.plain = std::make_unique<Scene>(plain_view_->build(o, in_.frame, models()));
        b.pair.plain = b.plain->camera.get();
      }
      b.ok = true;
    } catch (const std::exception&) {
    }
    return b;
  }

  const Scene& models() const { return in_.models ? *in_.models : *in_.loaded; }

  const SolveInput& in_;
  const FreeValues& free_;
  bool plain_;
  size_t capacity_;
  ViewTemplate view_;
  std::optional<ViewTemplate> plain_view_;
  std::vector<std::shared_ptr<Built>> cache_;
  size_t next_ = 0;
  std::vector<std::optional<CameraKey>> keys_;
};

// Magnification: Ceres' central differences of its whole residual (through the inverse map): its
// chain rule (Goals::derivative) agrees with differences where tested but sent a coin's radius to
// its bound on SolveCli.RecoversACoinsStrengthAndRadiusFromMagnificationAndAPin (docs/solve.md).
struct GoalCost {
  const Goals* goals;
  size_t index;
  CameraBuilder* builder;
  bool operator()(double const* const* p, double* r) const {
    const CameraPair* cam = builder->at(p[0]);
    if (!cam) return false;
    goals->residuals(index, *cam, r);
    for (int k = 0; k < goals->residual_count(index); ++k)
      if (!std::isfinite(r[k])) return false;
    return true;
  }
};

// Every other constraint's residuals r(uv(k), k) with uv the image positions of its world points
// (Goals::points). The Jacobian by the chain rule, never through differences of the inverse map:
// dr/dk = dr/duv duv/dk + (dr/dk at fixed uv), with duv/dk by image_position_derivative (the
// implicit function theorem: the rays at uv, analytic in uv, and their derivative with respect to
// the key, exact from the camera where it gives one (VirtualCamera::key_derivative), else through
// the cameras at x -+ h),
// dr/duv by central differences of residuals_at in uv (closed-form functions of the positions, or
// for magnification of the rays there) and the last term, only for magnification, by the rays at
// the same uv through the cameras at x -+ h.
class ChainCost : public ceres::CostFunction {
 public:
  ChainCost(const Goals& goals, size_t index, CameraBuilder& builder, int n,
            const std::vector<std::optional<CameraKey>>& keys)
      : goals_(goals), index_(index), builder_(builder), keys_(keys) {
    set_num_residuals(goals.residual_count(index));
    mutable_parameter_block_sizes()->push_back(n);
  }

  bool Evaluate(double const* const* p, double* r, double** jac) const override {
    const std::shared_ptr<const CameraPair> c0 = builder_.hold(p[0]);
    if (!c0) return false;
    const std::vector<Vec2> uv = goals_.positions(index_, *c0->camera);
    goals_.residuals_at(index_, *c0, uv, r);
    for (int k = 0; k < num_residuals(); ++k)
      if (!std::isfinite(r[k])) return false;
    if (!jac || !jac[0]) return true;
    const std::vector<std::vector<double>> dr_duv = goals_.by_positions(index_, *c0, uv);
    const int n = parameter_block_sizes()[0], m = num_residuals();
    std::vector<double> x(p[0], p[0] + n);
    std::vector<double> col(static_cast<size_t>(m));
    for (int j = 0; j < n; ++j) {
      if (!exact_column(*c0, size_t(j), uv, dr_duv, col.data()) &&
          !difference_column(c0, x, j, uv, dr_duv, col.data()))
        return false;
      for (int i = 0; i < m; ++i) jac[0][size_t(i * n + j)] = col[size_t(i)];
    }
    return true;
  }

 private:
  // Column j with duv/dk from the camera's exact ray derivative (VirtualCamera::key_derivative);
  // false where it gives none (then by differences). Magnification's term at fixed positions is a
  // derivative of the ray differentials, which the camera does not give: by differences.
  bool exact_column(const CameraPair& c0, size_t j, const std::vector<Vec2>& uv,
                    const std::vector<std::vector<double>>& dr_duv, double* col) const {
    const auto* cam = dynamic_cast<const VirtualCamera*>(c0.camera);
    if (!cam || !keys_[j] || goals_.moves_at_fixed_positions(index_)) return false;
    const CameraKey& key = *keys_[j];
    const PositionDerivative exact = [&](const Vec3& p, Vec2 at, Vec2* d) {
      Vec3 dorg, ddir;
      return cam->key_derivative(key, at, &dorg, &ddir) &&
             image_position_derivative(*cam, p, at, dorg, ddir, d);
    };
    return goals_.derivative(index_, exact, uv, dr_duv, col);
  }

  // Column j through the cameras rebuilt with the key at x -+ h.
  bool difference_column(const std::shared_ptr<const CameraPair>& c0, std::vector<double>& x, int j,
                         const std::vector<Vec2>& uv,
                         const std::vector<std::vector<double>>& dr_duv, double* col) const {
    const double x0 = x[size_t(j)], step = 1e-6 * (x0 == 0 ? 1 : std::abs(x0));  // (as Ceres')
    x[size_t(j)] = x0 + step;
    std::shared_ptr<const CameraPair> hi = builder_.hold(x.data());
    x[size_t(j)] = x0 - step;
    std::shared_ptr<const CameraPair> lo = builder_.hold(x.data());
    x[size_t(j)] = x0;
    const double span = (hi ? step : 0) + (lo ? step : 0);  // one-sided where one is refused
    if (!hi) hi = c0;
    if (!lo) lo = c0;
    return goals_.derivative(index_, *c0, *lo, *hi, span, uv, dr_duv, col);
  }

  const Goals& goals_;
  size_t index_;
  CameraBuilder& builder_;
  const std::vector<std::optional<CameraKey>>& keys_;
};

struct Run {
  std::vector<double> x;
  int iterations = 0;
  std::string termination;
};

// Solves the constraints `subset` from `x0`.
Run run(const std::vector<size_t>& subset, const std::vector<double>& x0, const Goals& goals,
        const FreeValues& free, const SolveOptions& opt, CameraBuilder& builder) {
  Run out{x0, 0, {}};
  double* x = out.x.data();
  const int n = int(x0.size());
  ceres::Problem problem;
  for (size_t i : subset) {
    ceres::CostFunction* cost = nullptr;
    if (goals.moves_at_fixed_positions(i)) {
      auto* numeric = new ceres::DynamicNumericDiffCostFunction<GoalCost, ceres::CENTRAL>(
          new GoalCost{&goals, i, &builder});
      numeric->AddParameterBlock(n);
      numeric->SetNumResiduals(goals.residual_count(i));
      cost = numeric;
    } else {
      cost = new ChainCost(goals, i, builder, n, builder.keys());
    }
    ceres::LossFunction* loss = nullptr;
    if (opt.loss == "huber") loss = new ceres::HuberLoss(opt.loss_scale);
    if (opt.loss == "cauchy") loss = new ceres::CauchyLoss(opt.loss_scale);
    const double w = goals.constraint(i).weight;
    problem.AddResidualBlock(cost, new ceres::ScaledLoss(loss, w * w, ceres::TAKE_OWNERSHIP), x);
  }
  for (int k = 0; k < n; ++k) {
    const FreeScalar& s = free.scalars[size_t(k)];
    if (std::isfinite(s.lo)) problem.SetParameterLowerBound(x, k, s.lo);
    if (std::isfinite(s.hi)) problem.SetParameterUpperBound(x, k, s.hi);
  }
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_QR;
  o.max_num_iterations = opt.max_iterations;
  o.function_tolerance = 1e-16;
  o.gradient_tolerance = 1e-20;
  o.parameter_tolerance = 1e-15;
  o.num_threads = 1;
  o.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  // Ceres logs a failed evaluation through glog to stderr ("Logging before InitGoogleLogging",
  // "Terminating: ..."); the report says what happened, in the user's terms.
  FLAGS_minloglevel = std::max(FLAGS_minloglevel, int(google::GLOG_FATAL));
  ceres::Solve(o, &problem, &summary);
  out.iterations = int(summary.iterations.size());
  out.termination = summary.message;
  return out;
}

std::vector<size_t> all_of(size_t n) {
  std::vector<size_t> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = i;
  return v;
}

ConstraintReport report(const Goals& goals, size_t i, const CameraPair& cam) {
  const CameraConstraint& c = goals.constraint(i);
  ConstraintReport r;
  r.where = c.where, r.kind = c.kind, r.unit = goals.unit(i);
  r.residual = goals.measure(i, cam);
  r.tolerance = c.tolerance;
  r.met = r.residual <= c.tolerance;
  return r;
}

bool met(const Goals& goals, size_t i, CameraBuilder& b, const std::vector<double>& x) {
  const CameraPair* cam = b.at(x.data());
  return cam && goals.measure(i, *cam) <= goals.constraint(i).tolerance;
}

// For each constraint not met: is it met alone (from the start)? Then which one it cannot be met
// together with (pairs solved from the start; up to 12 constraints).
void explain_unmet(SolveReport& rep, const Goals& goals, const FreeValues& free,
                   const std::vector<double>& x0, const SolveOptions& opt, CameraBuilder& b) {
  for (size_t i = 0; i < goals.size(); ++i) {
    ConstraintReport& r = rep.constraints[i];
    if (r.met) continue;
    r.met_alone = met(goals, i, b, run({i}, x0, goals, free, opt, b).x);
    if (!r.met_alone || goals.size() > 12) continue;
    for (size_t j = 0; j < goals.size(); ++j) {
      if (j == i) continue;
      const std::vector<double> x = run({i, j}, x0, goals, free, opt, b).x;
      if (!met(goals, i, b, x) || !met(goals, j, b, x))
        r.conflicts.push_back(goals.constraint(j).where);
    }
  }
}

}  // namespace

bool SolveReport::all_met() const {
  for (const ConstraintReport& c : constraints)
    if (!c.met) return false;
  return true;
}

SolveReport solve_camera(const SolveInput& in) {
  const Scene& loaded = *in.loaded;
  const toml::table root = parse_toml(loaded.effective_toml, in.file.string());
  const toml::table* cam_table = root.get_as<toml::table>("camera");
  const toml::table empty;
  const CameraGoals g = read_camera_goals(TableReader(cam_table ? *cam_table : empty, "camera"));
  const SourceLoc at{in.file.string(), 0, 0};
  if (g.constraints.empty())
    throw SceneError(at, "camera.constraint", "no [[camera.constraint]] to solve for");
  if (g.free.empty()) throw SceneError(at, "camera.free", "no [[camera.free]] key to solve for");
  const FreeValues free = resolve_free(g.free, root, loaded.animated, in.file.string());
  const Goals goals(g, loaded, *loaded.camera, loaded.render.width, loaded.render.height);
  CameraBuilder builder(in, free, goals.needs_plain());
  const std::vector<double> x0 = in.start.empty() ? free.start() : in.start;
  if (x0.size() != free.scalars.size())
    throw SceneError(at, "camera.free", "the start values do not match the free keys");
  if (!builder.at(x0.data()))
    throw SceneError(at, "camera", "the camera cannot be built at the start values");

  SolveOptions opt = g.options;
  if (in.max_iterations > 0) opt.max_iterations = std::min(opt.max_iterations, in.max_iterations);
  const Run best = run(all_of(goals.size()), x0, goals, free, opt, builder);
  SolveReport rep;
  rep.iterations = best.iterations;
  rep.termination = best.termination;
  rep.texts = free.texts(best.x);
  for (size_t k = 0; k < free.scalars.size(); ++k) {
    const FreeScalar& s = free.scalars[k];
    const double v = best.x[k];
    rep.values.push_back({s.name, x0[k], v, s.lo, s.hi, v <= s.lo || v >= s.hi});
  }
  const CameraPair* cam = builder.at(best.x.data());
  if (!cam) throw SceneError(at, "camera", "the camera cannot be built at the solved values");
  for (size_t i = 0; i < goals.size(); ++i) rep.constraints.push_back(report(goals, i, *cam));
  if (!rep.all_met() && in.explain) explain_unmet(rep, goals, free, x0, opt, builder);
  return rep;
}

}  // namespace anamorph::solve
