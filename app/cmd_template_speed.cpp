// polarcam template-speed --thickness H --roller-radius R [--radius-of-curvature RHO ...] [--plot FIG] [--json]
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "app/cli.hpp"
#include "cam/error.hpp"
#include "cam/format.hpp"
#include "digitizer/template_speed.hpp"
#include "io/output.hpp"
#include "report/template_figure.hpp"

namespace polarcam::cli {
namespace cmd_template_speed {  // named, not anonymous: the command files are compiled together (unity build)

struct Opts {
  std::string thickness, plot;
  std::vector<std::string> rollers, radii;
  double rho_star_max = 50.0;
  bool json = false;
};

// v* where the rollers can follow the radius on that side, nothing where they cannot
std::optional<double> v_star(double rho_star, double rr, CurvatureSide side) {
  const double lo = side == CurvatureSide::roller ? rr : 1.0 + rr;
  if (side == CurvatureSide::roller ? !(rho_star > lo) : !(rho_star >= lo)) return std::nullopt;
  return template_v_star(rho_star, rr, side);
}

int run(const Opts& o) {
  const double H = option_quantity(o.thickness, dim::length, "--thickness");
  if (!(H > 0.0)) throw InputError("must be a positive length", "--thickness");
  std::vector<double> R;
  for (const std::string& r : o.rollers) {
    R.push_back(option_quantity(r, dim::length, "--roller-radius"));
    if (!(R.back() > 0.0)) throw InputError("must be a positive length", "--roller-radius");
  }
  std::vector<double> rho;
  for (const std::string& r : o.radii) {
    rho.push_back(option_quantity(r, dim::length, "--radius-of-curvature"));
    if (!(rho.back() > 0.0)) throw InputError("must be a positive length", "--radius-of-curvature");
  }
  if (rho.empty())
    for (double k : {1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0}) rho.push_back(k * H);
  if (!(o.rho_star_max > 1.0) || o.rho_star_max > 1e6) throw InputError("must be a number above 1 and up to 1e6", "--rho-star-max");
  if (!o.plot.empty()) plot::check_plot_path(o.plot);

  if (!o.plot.empty()) {
    TemplateFigureOptions fo;
    for (double r : R) fo.rr_stars.push_back(r / H);
    fo.rho_star_max = o.rho_star_max;
    if (!o.radii.empty()) fo.mark_rho_star = rho.front() / H;
    write_files_atomic({{o.plot, plot::render(template_speed_figure(fo), plot::plot_format(o.plot))}});
  }

  if (o.json) {
    nlohmann::ordered_json j;
    j["thickness_m"] = H;
    j["rollers"] = nlohmann::ordered_json::array();
    for (double r : R) {
      const double rr = r / H;
      nlohmann::ordered_json jr;
      jr["roller_radius_m"] = r;
      jr["rr_star"] = rr;
      jr["min_radius_roller_side_m"] = r;  // exclusive: the roller stops there
      jr["min_radius_other_side_m"] = H + r;
      jr["points"] = nlohmann::ordered_json::array();
      for (double p : rho) {
        nlohmann::ordered_json jp;
        jp["radius_of_curvature_m"] = p;
        jp["rho_star"] = p / H;
        const auto a = v_star(p / H, rr, CurvatureSide::roller), b = v_star(p / H, rr, CurvatureSide::other);
        jp["v_star_roller_side"] = a ? nlohmann::ordered_json(*a) : nlohmann::ordered_json();
        jp["v_star_other_side"] = b ? nlohmann::ordered_json(*b) : nlohmann::ordered_json();
        jr["points"].push_back(jp);
      }
      j["rollers"].push_back(jr);
    }
    if (!o.plot.empty()) j["plot"] = o.plot;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::ostringstream os;
  auto mm = [](double v) { return significant(v * 1e3, 6) + " mm"; };
  auto cell = [](std::optional<double> v) {
    if (!v) return std::string("    cannot follow       ");
    char b[64];
    std::snprintf(b, sizeof b, "%10.6f  %+8.3f %%  ", *v, 100.0 * (*v - 1.0));
    return std::string(b);
  };
  os << "template digitizer speed, v = V_t v* (Eq. 3.3 with the factor 2 of Eq. 3.2); thickness H = " << mm(H) << "\n";
  for (double r : R) {
    const double rr = r / H;
    os << "  roller radius " << mm(r) << " (R_r* = " << significant(rr, 6) << "): follows radii of curvature above "
       << mm(r) << " on its side, from " << mm(H + r) << " on the other\n";
    os << "    radius of curvature       rho*    v* (3.3a)     error     v* (3.3b)     error\n";
    for (double p : rho) {
      char b[64];
      std::snprintf(b, sizeof b, "    %-20s %9.4g  ", mm(p).c_str(), p / H);
      os << b << cell(v_star(p / H, rr, CurvatureSide::roller)) << cell(v_star(p / H, rr, CurvatureSide::other)) << "\n";
    }
  }
  if (!o.plot.empty()) os << "  figure " << o.plot << "\n";
  std::cout << os.str();
  return 0;
}

}  // namespace cmd_template_speed

void register_template_speed(CLI::App& app, Action& action) {
  using namespace cmd_template_speed;
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand(
      "template-speed",
      "The template digitizer's contouring speed against the radius of curvature (Eq. 3.3, Fig. 3.2)");
  c->add_option("--thickness", o->thickness, "template thickness H, e.g. \"1/8 in\"")->required();
  c->add_option("--roller-radius", o->rollers, "roller radius R_r (repeat for several curves)")->required();
  c->add_option("--radius-of-curvature", o->radii,
                "print v* at these radii of curvature (repeatable; default 1 to 100 H); the first is marked on the plot");
  CLI::Option* rho_max = c->add_option("--rho-star-max", o->rho_star_max, "right end of the plot's rho* axis (default 50)");
  rho_max->needs(c->add_option("--plot", o->plot, "draw Fig. 3.2 to this .png or .svg file"));
  c->add_flag("--json", o->json, "print the table as one JSON object");
  c->callback([o, &action] { action = [o] { return run(*o); }; });
}

}  // namespace polarcam::cli
