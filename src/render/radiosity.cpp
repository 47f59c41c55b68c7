#include "render/radiosity.h"

#include <fmt/format.h>
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "render/surface_sampler.h"

namespace anamorph {

namespace {

constexpr const char* kChannel[] = {"red", "green", "blue"};

// The materials of object `id`'s surface (one for a shape, one per mesh of a model).
std::vector<uint32_t> object_materials(const Accel& accel, uint32_t id) {
  const Accel::Record& r = accel.record(id);
  switch (r.kind) {
    case Accel::Record::Kind::FlatMesh:
      return {r.mesh->material};
    case Accel::Record::Kind::Instance: {
      std::vector<uint32_t> m;
      for (const TriangleMesh& mesh : r.proto->meshes) m.push_back(mesh.material);
      return m.empty() ? std::vector<uint32_t>{0} : m;
    }
    case Accel::Record::Kind::Shape:
      return {r.shape->material};
  }
  return {0};
}

const Material& object_material(const Scene& scene, const Accel& accel, uint32_t id) {
  return *scene.materials[object_materials(accel, id).front()];
}

// "'lamp' (material 'bright')": how messages name an object and its material.
std::string object_and_material(const std::string& object, const Material& m) {
  return fmt::format("'{}' (material '{}')", object, m.name);
}

// The inverse-variance mean of the exchange A_i F_ij = A_j F_ji measured from both sides, with
// standard errors si and sj of the two products: weights 1/s^2 written as a ratio of the two
// errors, which neither underflows nor overflows for areas of any size.
double combined_exchange(double from_i, double si, double from_j, double sj) {
  if (si <= sj) {
    const double r = si / sj;
    return (from_i + r * r * from_j) / (1 + r * r);
  }
  const double r = sj / si;
  return (r * r * from_i + from_j) / (1 + r * r);
}

// The objects that reflect all light in channel c (reflectance 1) and whose rays, as measured,
// reach only each other (not the environment, nor an object that absorbs): light that enters
// them is never absorbed, so (I - rho F) is singular there. Empty for a well-posed system.
std::vector<size_t> lossless_enclosure(const Scene& scene, const Accel& accel, const FormFactors& f,
                                       const std::vector<int>& row_of, int c) {
  const size_t n = f.names.size();
  std::vector<bool> in(n);
  for (size_t i = 0; i < n; ++i)
    in[i] = object_reflectance(scene, accel, uint32_t(i))[c] == 1 &&
            f.F[size_t(row_of[i])][n] == 0;  // (column n: the environment)
  for (bool changed = true; changed;) {
    changed = false;
    for (size_t i = 0; i < n; ++i)
      for (size_t j = 0; j < n && in[i]; ++j)
        if (!in[j] && f.F[size_t(row_of[i])][j] > 0) in[i] = false, changed = true;
  }
  std::vector<size_t> out;
  for (size_t i = 0; i < n; ++i)
    if (in[i]) out.push_back(i);
  return out;
}

}  // namespace

Color object_reflectance(const Scene& scene, const Accel& accel, uint32_t id) {
  return object_material(scene, accel, id).diffuse_reflectance();
}

Color object_emission(const Scene& scene, const Accel& accel, uint32_t id) {
  const Material& m = object_material(scene, accel, id);
  return m.emission.value * (m.emission_strength * kPi);
}

void check_radiosity_inputs(const Scene& scene, const Accel& accel,
                            const std::vector<std::string>& inward) {
  std::vector<std::string> notes;
  const std::vector<std::string> names = form_factor_names(accel, &notes);
  for (uint32_t i = 0; i < names.size(); ++i) {
    const bool in = std::find(inward.begin(), inward.end(), names[i]) != inward.end();
    const MeasurableSurface s = measurable_surface(accel.record(i), in);
    if (!s.sampler)
      throw std::invalid_argument(fmt::format(
          "radiosity needs a row of form factors for every object, and '{}' can have none: {}",
          names[i], s.problem));
    const std::vector<uint32_t> mats = object_materials(accel, i);
    if (std::any_of(mats.begin(), mats.end(), [&](uint32_t m) { return m != mats.front(); }))
      throw std::invalid_argument(fmt::format(
          "radiosity needs one material per object, and '{}' has {} meshes with different "
          "materials",
          names[i], mats.size()));
    const Material& m = *scene.materials[mats.front()];
    for (const auto& [texture, key] :
         {std::pair{&m.base_color, "colour"}, std::pair{&m.emission, "emission"}})
      if (texture->kind != Texture::Kind::Constant)
        throw std::invalid_argument(fmt::format(
            "radiosity needs one {} per object, and {} has a textured {}: give it a constant one",
            key, object_and_material(names[i], m), key));
    const Color rho = object_reflectance(scene, accel, i), e = object_emission(scene, accel, i);
    for (int c = 0; c < 3; ++c) {
      if (!(rho[c] >= 0 && rho[c] <= 1))
        throw std::invalid_argument(fmt::format(
            "{} reflects {} of the light in the {} channel: radiosity needs a reflectance within "
            "[0, 1]",
            object_and_material(names[i], m), rho[c], kChannel[c]));
      if (!(e[c] >= 0 && std::isfinite(e[c])))
        throw std::invalid_argument(fmt::format(
            "{} emits {} in the {} channel (pi x emission x emission_strength): radiosity needs a "
            "finite emission",
            object_and_material(names[i], m), e[c], kChannel[c]));
    }
  }
}

namespace {

// Each pair's exchange A_i F_ij = A_j F_ji is measured twice, from either side, usually with
// very different errors (a small lamp's row measures its exchange with a big room far more
// precisely than the room's row does): the two combined by inverse variance, by object index.
std::vector<std::vector<double>> combined_form_factors(const FormFactors& f,
                                                       const std::vector<int>& row_of) {
  const size_t n = row_of.size();
  std::vector<std::vector<double>> F(n, std::vector<double>(n));
  for (size_t a = 0; a < n; ++a)
    for (size_t j = 0; j < n; ++j) F[size_t(f.rows[a])][j] = f.F[a][j];
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      const double Ai = f.areas[i], Aj = f.areas[j];
      const double si = Ai * f.error[size_t(row_of[i])][j], sj = Aj * f.error[size_t(row_of[j])][i];
      const double g = combined_exchange(Ai * F[i][j], si, Aj * F[j][i], sj);
      F[i][j] = g / Ai, F[j][i] = g / Aj;
    }
  return F;
}

}  // namespace

std::vector<Color> solve_radiosity(const Scene& scene, const Accel& accel, const FormFactors& f) {
  const int n = int(f.rows.size());
  if (size_t(n) != f.names.size())
    throw std::invalid_argument(
        "radiosity needs a row of form factors for every object (all with finite area)");
  std::vector<int> row_of(static_cast<size_t>(n));
  for (int a = 0; a < n; ++a) row_of[size_t(f.rows[size_t(a)])] = a;
  const std::vector<std::vector<double>> F = combined_form_factors(f, row_of);
  std::vector<Color> B(static_cast<size_t>(n));
  for (int c = 0; c < 3; ++c) {
    if (const auto closed = lossless_enclosure(scene, accel, f, row_of, c); !closed.empty()) {
      std::string list;
      for (const size_t i : closed) list += (list.empty() ? "'" : ", '") + f.names[i] + "'";
      throw std::invalid_argument(fmt::format(
          "the radiosity system (I - rho F) B = E has no solution in the {} channel: {} reflect{} "
          "all light (reflectance 1) and {} only each other, so light is never absorbed and "
          "there is no steady state: give {} a reflectance below 1",
          kChannel[c], list, closed.size() == 1 ? "s" : "", closed.size() == 1 ? "sees" : "see",
          closed.size() == 1 ? "it" : "one of them"));
    }
    Eigen::MatrixXd A = Eigen::MatrixXd::Identity(n, n);
    Eigen::VectorXd E(n);
    for (int i = 0; i < n; ++i) {
      const double rho = object_reflectance(scene, accel, uint32_t(i))[c];
      E(i) = object_emission(scene, accel, uint32_t(i))[c];
      for (int j = 0; j < n; ++j) A(i, j) -= rho * F[size_t(i)][size_t(j)];
    }
    const Eigen::VectorXd x = A.fullPivLu().solve(E);
    // With reflectances in [0, 1], rows of F summing to at most 1 and no lossless enclosure,
    // I - rho F is a non-singular M-matrix whose solution is finite and non-negative: this
    // holds it to that (the combined F's rounding aside).
    const double scale = std::max(E.cwiseAbs().maxCoeff(), 1e-300);
    const bool solved = x.allFinite() && (A * x - E).cwiseAbs().maxCoeff() <=
                                             1e-9 * scale + 1e-12 * x.cwiseAbs().maxCoeff();
    if (!solved || x.minCoeff() < -1e-9 * x.cwiseAbs().maxCoeff()) {
      int worst = 0;
      for (int i = 1; i < n; ++i)
        if (!(x(i) >= x(worst))) worst = i;
      throw std::invalid_argument(fmt::format(
          "the radiosity system (I - rho F) B = E has no {} solution in the {} channel{}: the "
          "measured form factors with reflectances this close to 1 leave it (nearly) singular",
          solved ? "non-negative" : "finite", kChannel[c],
          solved ? fmt::format(" (B of '{}' would be {:.6g})", f.names[size_t(worst)], x(worst))
                 : ""));
    }
    for (int i = 0; i < n; ++i) B[size_t(i)][c] = std::max(x(i), 0.0);
  }
  return B;
}

}  // namespace anamorph
