// polarcam trace IMAGE -o OUT.svg [--pixel-size Q] [--threshold X] [--invert] [--despeckle N] [--json]
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/cli.hpp"
#include "cam/error.hpp"
#include "cam/format.hpp"
#include "cam/image_trace.hpp"
#include "io/output.hpp"

namespace polarcam::cli {

void register_trace(CLI::App& app, Action& action) {
  struct Opts {
    std::string image, out;
    PatternArgs trace;
    bool json = false;
  };
  auto o = std::make_shared<Opts>();
  CLI::App* c = app.add_subcommand("trace", "Trace a template image (PNG, PBM, PGM) into contours: outlines and "
                                            "holes as an SVG drawing of the template's physical size");
  c->add_option("image", o->image, "the template image (.png, .pbm, .pgm)")->required();
  c->add_option("-o,--output", o->out, "the SVG drawing to write")->required();
  add_trace_options(c, o->trace);
  c->add_flag("--json", o->json, "print what was traced as one JSON object");
  c->callback([o, &action] {
    action = [o] {
      const TraceOptions t = trace_options(o->trace);
      check_output_path(o->out);
      check_output_extension(o->out, {".svg"}, "the traced drawing");
      const Tracing tr = trace_image(read_image(o->image), t, o->image);
      write_file_atomic(o->out, tracing_svg(tr, std::filesystem::path(o->image).filename().string()));
      size_t holes = 0;
      for (const TracedContour& k : tr.contours) holes += k.hole;
      nlohmann::ordered_json j;
      j["image"] = o->image;
      j["pixels"] = {tr.width_px, tr.height_px};
      j["pixel_size_m"] = tr.pixel_size_m;
      j["width_m"] = tr.width_m();
      j["height_m"] = tr.height_m();
      j["ink_pixels"] = tr.ink_px;
      j["contours"] = tr.contours.size();
      j["outlines"] = tr.contours.size() - holes;
      j["holes"] = holes;
      j["output"] = o->out;
      if (o->json) {
        std::cout << j.dump(2) << "\n";
        return 0;
      }
      std::cout << "polarcam trace " << o->image << "\n"
                << "  image      " << tr.width_px << " x " << tr.height_px << " pixels of "
                << significant(tr.pixel_size_m * 1e3, 4) << " mm: " << significant(tr.width_m() * 1e3, 6) << " x "
                << significant(tr.height_m() * 1e3, 6) << " mm\n"
                << "  contours   " << tr.contours.size() << " (" << count_of(tr.contours.size() - holes, "outline") << ", "
                << count_of(holes, "hole") << ")\n"
                << "  written    " << o->out << "\n";
      return 0;
    };
  });
}

}  // namespace polarcam::cli
