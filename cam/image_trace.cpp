#include "cam/image_trace.hpp"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include <png.h>
#include <potracelib.h>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "cam/input_file.hpp"

namespace polarcam {
namespace {

constexpr long long kMaxPixels = 1LL << 28;

void check_size(long long w, long long h, const std::string& place) {
  if (w <= 0 || h <= 0) throw InputError("the image is empty (" + std::to_string(w) + " x " + std::to_string(h) + " pixels)", place);
  if (w > INT_MAX / 2 || h > INT_MAX / 2 || w * h > kMaxPixels)
    throw InputError("the image has " + std::to_string(w) + " x " + std::to_string(h) +
                         " pixels, more than 2^28: scan at a lower resolution",
                     place);
}

// ---- PNG (libpng) ----

struct PngSource {
  const std::string* bytes;
  size_t at = 0;
};

struct PngFailure {
  char message[200] = {0};
};

void png_read_bytes(png_structp png, png_bytep out, png_size_t n) {
  auto* s = static_cast<PngSource*>(png_get_io_ptr(png));
  if (s->at + n > s->bytes->size()) png_error(png, "the file ends in the middle of the image");
  std::memcpy(out, s->bytes->data() + s->at, n);
  s->at += n;
}

void png_fail(png_structp png, png_const_charp msg) {
  auto* f = static_cast<PngFailure*>(png_get_error_ptr(png));
  std::snprintf(f->message, sizeof f->message, "%s", msg ? msg : "damaged PNG");
  png_longjmp(png, 1);
}

void png_quiet(png_structp, png_const_charp) {}

// The pixels as gray + alpha, 8 bits each. Between setjmp and the end of this function no object with a
// destructor is created (libpng leaves by longjmp on an error); the buffers live in the caller.
bool png_decode(PngSource* src, PngFailure* fail, std::vector<uint8_t>* ga, int* w_out, int* h_out, double* ppm_out) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, fail, png_fail, png_quiet);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_set_read_fn(png, src, png_read_bytes);
  png_set_user_limits(png, 1u << 20, 1u << 20);
  png_read_info(png, info);
  const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
  if (static_cast<long long>(w) * h > kMaxPixels || w > INT_MAX / 2 || h > INT_MAX / 2) {
    std::snprintf(fail->message, sizeof fail->message, "the image has %u x %u pixels, more than 2^28: scan at a lower resolution", w, h);
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_uint_32 ppm_x = 0, ppm_y = 0;
  int unit = 0;
  if (png_get_pHYs(png, info, &ppm_x, &ppm_y, &unit) && unit == PNG_RESOLUTION_METER && ppm_x > 0 && ppm_x == ppm_y)
    *ppm_out = ppm_x;
  png_set_expand(png);          // palette, low-depth gray and tRNS to 8-bit channels with alpha
  png_set_strip_16(png);
  png_set_rgb_to_gray_fixed(png, 1, -1, -1);  // the default weights (ITU-R BT.709 luminance)
  png_set_add_alpha(png, 0xff, PNG_FILLER_AFTER);
  const int passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);
  if (png_get_channels(png, info) != 2 || png_get_rowbytes(png, info) != 2 * static_cast<size_t>(w)) {
    std::snprintf(fail->message, sizeof fail->message, "unsupported PNG layout");
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  ga->resize(2 * static_cast<size_t>(w) * h);
  for (int pass = passes; pass > 0; --pass)
    for (png_uint_32 y = 0; y < h; ++y) png_read_row(png, ga->data() + 2 * static_cast<size_t>(w) * y, nullptr);
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  *w_out = static_cast<int>(w);
  *h_out = static_cast<int>(h);
  return true;
}

GrayImage parse_png(const std::string& bytes, const std::string& place) {
  PngSource src{&bytes, 0};
  PngFailure fail;
  std::vector<uint8_t> ga;
  int w = 0, h = 0;
  double ppm = 0.0;
  if (!png_decode(&src, &fail, &ga, &w, &h, &ppm))
    throw InputError(std::string("not a readable PNG image: ") + (fail.message[0] ? fail.message : "out of memory"), place);
  check_size(w, h, place);
  GrayImage im;
  im.width = w;
  im.height = h;
  im.luminance.resize(static_cast<size_t>(w) * h);
  for (size_t i = 0; i < im.luminance.size(); ++i) {
    // composited onto white paper: l a + 255 (1 - a)
    const unsigned l = ga[2 * i], a = ga[2 * i + 1];
    im.luminance[i] = static_cast<uint8_t>((l * a + 255u * (255u - a) + 127u) / 255u);
  }
  if (ppm > 0.0) im.pixel_size_m = 1.0 / ppm;
  return im;
}

// ---- PBM / PGM (netpbm's plain and raw formats) ----

class PnmReader {
 public:
  PnmReader(const std::string& b, const std::string& place) : b_(b), place_(place) {}

  // The next header or plain-format number; comments (# to the end of the line) and white space skipped.
  long long number(const char* what) {
    skip_space();
    if (at_ >= b_.size() || !std::isdigit(static_cast<unsigned char>(b_[at_])))
      throw InputError(std::string("damaged netpbm image: expected ") + what + " at byte " + std::to_string(at_), place_);
    long long v = 0;
    while (at_ < b_.size() && std::isdigit(static_cast<unsigned char>(b_[at_]))) {
      v = v * 10 + (b_[at_++] - '0');
      if (v > (1LL << 40)) throw InputError(std::string("damaged netpbm image: ") + what + " out of range", place_);
    }
    return v;
  }
  // A plain PBM's pixel: one '0' or '1', with or without space around it.
  int bit() {
    skip_space();
    if (at_ >= b_.size() || (b_[at_] != '0' && b_[at_] != '1'))
      throw InputError("the image ends early or holds something other than 0 and 1 at byte " + std::to_string(at_), place_);
    return b_[at_++] - '0';
  }
  // The single white-space byte between a raw format's header and its pixels.
  void raster_start() {
    if (at_ >= b_.size() || !std::isspace(static_cast<unsigned char>(b_[at_])))
      throw InputError("damaged netpbm image: no white space before the pixels", place_);
    ++at_;
  }
  const uint8_t* raw(size_t n) {
    if (b_.size() - at_ < n)
      throw InputError("the image ends early: " + std::to_string(n) + " bytes of pixels expected, " +
                           std::to_string(b_.size() - at_) + " found",
                       place_);
    const auto* p = reinterpret_cast<const uint8_t*>(b_.data() + at_);
    at_ += n;
    return p;
  }

 private:
  void skip_space() {
    while (at_ < b_.size()) {
      if (b_[at_] == '#') {
        while (at_ < b_.size() && b_[at_] != '\n' && b_[at_] != '\r') ++at_;
      } else if (std::isspace(static_cast<unsigned char>(b_[at_]))) {
        ++at_;
      } else {
        break;
      }
    }
  }
  const std::string& b_;
  const std::string& place_;
  size_t at_ = 2;  // after the magic number
};

GrayImage parse_pnm(const std::string& bytes, const std::string& place) {
  const char kind = bytes[1];
  PnmReader r(bytes, place);
  const long long w = r.number("the width"), h = r.number("the height");
  check_size(w, h, place);
  long long maxval = 1;
  if (kind == '2' || kind == '5') {
    maxval = r.number("the largest gray value");
    if (maxval < 1 || maxval > 65535) throw InputError("damaged PGM image: the largest gray value must be 1 to 65535", place);
  }
  GrayImage im;
  im.width = static_cast<int>(w);
  im.height = static_cast<int>(h);
  const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
  im.luminance.resize(n);
  auto gray = [&](long long v) -> uint8_t {
    if (v > maxval) throw InputError("a gray value " + std::to_string(v) + " is above the image's largest, " + std::to_string(maxval), place);
    return static_cast<uint8_t>((v * 255 + maxval / 2) / maxval);
  };
  if (kind == '1') {
    for (size_t i = 0; i < n; ++i) im.luminance[i] = r.bit() ? 0 : 255;  // 1 is black
  } else if (kind == '4') {
    r.raster_start();
    const size_t row = (static_cast<size_t>(w) + 7) / 8;
    const uint8_t* p = r.raw(row * static_cast<size_t>(h));
    for (long long y = 0; y < h; ++y)
      for (long long x = 0; x < w; ++x)
        im.luminance[y * w + x] = ((p[y * row + x / 8] >> (7 - x % 8)) & 1) ? 0 : 255;
  } else if (kind == '2') {
    for (size_t i = 0; i < n; ++i) im.luminance[i] = gray(r.number("a gray value"));
  } else {
    r.raster_start();
    const size_t bpp = maxval > 255 ? 2 : 1;
    const uint8_t* p = r.raw(n * bpp);
    for (size_t i = 0; i < n; ++i) im.luminance[i] = gray(bpp == 2 ? (p[2 * i] << 8 | p[2 * i + 1]) : p[i]);
  }
  return im;
}

// ---- tracing ----

struct PotraceState {
  potrace_state_t* st = nullptr;
  ~PotraceState() {
    if (st) potrace_state_free(st);
  }
};

Vec2 at(const potrace_dpoint_t& p, double s) { return {p.x * s, p.y * s}; }

CurvePtr contour_curve(const potrace_curve_t& c, double s, const std::string& name) {
  std::vector<CurveSegment> segs;
  segs.reserve(2 * static_cast<size_t>(c.n));
  Vec2 from = at(c.c[c.n - 1][2], s);
  for (int i = 0; i < c.n; ++i) {
    const Vec2 end = at(c.c[i][2], s);
    if (c.tag[i] == POTRACE_CORNER) {
      const Vec2 corner = at(c.c[i][1], s);
      if (!(corner == from)) segs.push_back(line_segment(from, corner));
      if (!(end == corner)) segs.push_back(line_segment(corner, end));
    } else {
      segs.push_back(cubic_segment(from, at(c.c[i][0], s), at(c.c[i][1], s), end));
    }
    from = end;
  }
  return make_segment_curve(std::move(segs), true, name);
}

std::string mm(double metres) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", metres * 1e3);
  std::string s = buf;
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  if (s == "-0") s = "0";
  return s;
}

}  // namespace

bool is_image_file(const std::string& path) {
  const std::string e = lower_extension(path);
  return e == ".png" || e == ".pbm" || e == ".pgm";
}

GrayImage parse_image(const std::string& bytes, const std::string& place) {
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() >= 8 && std::memcmp(bytes.data(), kPng, 8) == 0) return parse_png(bytes, place);
  if (bytes.size() >= 2 && bytes[0] == 'P' && (bytes[1] == '1' || bytes[1] == '2' || bytes[1] == '4' || bytes[1] == '5'))
    return parse_pnm(bytes, place);
  if (bytes.empty()) throw InputError("the image file is empty", place);
  throw InputError("not an image polarcam reads: give a PNG, PBM or PGM file", place);
}

GrayImage read_image(const std::string& path) {
  std::ifstream in = open_input_file(path, "cannot open the image");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw DeviceError("cannot read the image", path);
  return parse_image(ss.str(), path);
}

Tracing trace_image(const GrayImage& im, const TraceOptions& o, const std::string& place) {
  if (!(o.threshold > 0.0 && o.threshold <= 1.0)) throw InputError("the threshold must be above 0 and at most 1", "--threshold");
  if (o.despeckle < 0) throw InputError("the despeckle area must be 0 or more pixels", "--despeckle");
  if (!(o.corner_threshold >= 0.0 && o.corner_threshold <= 4.0 / 3.0))
    throw InputError("the corner threshold must be 0 to 4/3", "--corner-threshold");
  if (!(o.curve_tolerance >= 0.0 && o.curve_tolerance <= 10.0)) throw InputError("the curve tolerance must be 0 to 10 pixels", "--curve-tolerance");
  check_size(im.width, im.height, place);
  if (im.luminance.size() != static_cast<size_t>(im.width) * static_cast<size_t>(im.height))
    throw InputError("the image's pixels do not match its size", place);
  const std::optional<double> size = o.pixel_size_m ? o.pixel_size_m : im.pixel_size_m;
  if (!size)
    throw InputError("the image does not state its resolution: give the size of a pixel, e.g. --pixel-size \"0.1 mm\"", place);
  if (!(*size >= 1e-9 && *size <= 1.0)) throw InputError("the pixel size must be 1 nm to 1 m", "--pixel-size");

  // potrace's bitmap: scanline 0 is the bottom row of the image (y up), the leftmost pixel the word's top bit
  constexpr int kBits = static_cast<int>(8 * sizeof(potrace_word));
  const int dy = (im.width + kBits - 1) / kBits;
  std::vector<potrace_word> map(static_cast<size_t>(dy) * static_cast<size_t>(im.height), 0);
  const double cut = o.threshold * 255.0;
  Tracing t;
  t.width_px = im.width;
  t.height_px = im.height;
  t.pixel_size_m = *size;
  for (int row = 0; row < im.height; ++row) {
    potrace_word* line = map.data() + static_cast<size_t>(dy) * static_cast<size_t>(im.height - 1 - row);
    const uint8_t* lum = im.luminance.data() + static_cast<size_t>(row) * static_cast<size_t>(im.width);
    for (int x = 0; x < im.width; ++x) {
      const bool ink = (lum[x] < cut) != o.invert;
      if (ink) {
        line[x / kBits] |= potrace_word(1) << (kBits - 1 - x % kBits);
        ++t.ink_px;
      }
    }
  }
  if (t.ink_px == 0) throw InputError("the image has no ink at this threshold: nothing to trace (check --threshold or --invert)", place);
  if (t.ink_px == static_cast<long>(im.width) * im.height)
    throw InputError("the image is all ink at this threshold: nothing to trace (check --threshold or --invert)", place);

  potrace_bitmap_t bm{im.width, im.height, dy, map.data()};
  std::unique_ptr<potrace_param_t, void (*)(potrace_param_t*)> param(potrace_param_default(), potrace_param_free);
  if (!param) throw std::bad_alloc();
  param->turdsize = o.despeckle;
  param->turnpolicy = POTRACE_TURNPOLICY_MINORITY;
  param->alphamax = o.corner_threshold;
  param->opticurve = o.curve_tolerance > 0.0 ? 1 : 0;
  param->opttolerance = o.curve_tolerance;
  PotraceState st;
  st.st = potrace_trace(param.get(), &bm);
  if (!st.st || st.st->status != POTRACE_STATUS_OK) throw std::bad_alloc();
  int outlines = 0, holes = 0;
  for (const potrace_path_t* p = st.st->plist; p; p = p->next) {
    if (p->curve.n <= 0) continue;
    const bool hole = p->sign == '-';
    const std::string name = hole ? "hole " + std::to_string(++holes) : "outline " + std::to_string(++outlines);
    TracedContour c;
    c.curve = in_file(place, [&] { return contour_curve(p->curve, *size, name); });
    c.hole = hole;
    c.area_px = p->area;
    t.contours.push_back(std::move(c));
  }
  if (t.contours.empty())
    throw InputError("no contour is left after despeckling (every spot is at most " + std::to_string(o.despeckle) +
                         " pixels): lower --despeckle",
                     place);
  return t;
}

std::string tracing_svg(const Tracing& t, const std::string& title) {
  const double H = t.height_m();
  auto pt = [&](Vec2 p) { return mm(p.x) + " " + mm(H - p.y); };
  std::ostringstream s;
  s << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << mm(t.width_m()) << "mm\" height=\"" << mm(H)
    << "mm\" viewBox=\"0 0 " << mm(t.width_m()) << " " << mm(H) << "\">\n"
    << "<title>" << xml_escape(title) << "</title>\n"
    << "<g fill=\"none\" stroke=\"black\" stroke-width=\"" << mm(t.pixel_size_m) << "\">\n";
  int outlines = 0, holes = 0;
  for (const TracedContour& c : t.contours) {
    const std::vector<CurveSegment>& segs = *curve_segments(*c.curve);
    s << "<path id=\"" << (c.hole ? "hole-" + std::to_string(++holes) : "outline-" + std::to_string(++outlines))
      << "\" d=\"M " << pt(segs.front().start());
    for (const CurveSegment& g : segs) {
      if (g.kind == CurveSegment::Kind::cubic)
        s << " C " << pt(g.p[1]) << " " << pt(g.p[2]) << " " << pt(g.p[3]);
      else
        s << " L " << pt(g.end());
    }
    s << " Z\"/>\n";
  }
  s << "</g>\n</svg>\n";
  return s.str();
}

}  // namespace polarcam
