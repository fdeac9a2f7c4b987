#pragma once
// The preview of a job, pattern or tape (pipeline/preview.hpp) as a figure: the work area, the tool path, the
// machine's stepped motion, the stretches below the requested speed, start and end.
#include <string>

#include "pipeline/preview.hpp"
#include "report/plot.hpp"

namespace polarcam::cli {

// The figure: one square panel.
plot::Figure preview_figure(const Preview& pv);
// Writes the figure to `path` (.png or .svg), all or nothing.
void save_preview(const Preview& pv, const std::string& path);

}  // namespace polarcam::cli
