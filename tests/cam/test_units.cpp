#include <gtest/gtest.h>

#include <numbers>

#include "cam/error.hpp"
#include "cam/format.hpp"
#include "cam/units.hpp"

namespace tu_cam_test_units {  // the test files of a program compile together (unity build)

using namespace polarcam;

TEST(Units, QuantitiesAreConvertedToSI) {
  EXPECT_DOUBLE_EQ(parse_quantity_as("7.62 cm", dim::length), 0.0762);
  EXPECT_DOUBLE_EQ(parse_quantity_as("0.001 in", dim::length), 2.54e-5);
  EXPECT_DOUBLE_EQ(parse_quantity_as("1.52 cm/s", dim::speed), 0.0152);
  EXPECT_DOUBLE_EQ(parse_quantity_as("3.438 ft/min", dim::speed), 3.438 * 0.3048 / 60);
  EXPECT_DOUBLE_EQ(parse_quantity_as("3*pi/4 rad", dim::angle), 3 * std::numbers::pi / 4);
  EXPECT_DOUBLE_EQ(parse_quantity_as("pi/2", dim::angle), std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(parse_quantity_as("90 deg", dim::angle), std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(parse_quantity_as("6.46e7 kN/m^2", dim::pressure), 6.46e10);
  EXPECT_DOUBLE_EQ(parse_quantity_as("0.068 V s/rad", dim::voltage * dim::time / dim::angle), 0.068);
  EXPECT_DOUBLE_EQ(parse_quantity_as("0.0759 N m/A", dim::torque / dim::current), 0.0759);
  EXPECT_DOUBLE_EQ(parse_quantity_as("20 rev/in", dim::angle / dim::length), 20 * 2 * std::numbers::pi / 0.0254);
  EXPECT_NEAR(parse_quantity_as("1 slug", dim::mass), 14.593903, 1e-6);
  EXPECT_NEAR(parse_quantity_as("0.094 lbf ft", dim::torque), 0.127447, 1e-5);
  EXPECT_DOUBLE_EQ(parse_quantity_as("1/s", dim::frequency), 1.0);
  EXPECT_DOUBLE_EQ(parse_quantity_as("5 mm/s^2", dim::acceleration), 5e-3);
}

TEST(Units, QuantitiesBeyondTheLimitInSIAreRefused) {
  // the limit is 1e30 in SI units: 1e31 mm is 1e28 m, within it; 1e308 in (2.54e306 m) and 1e28 km^2 are not, nor
  // is a plain 1e31
  EXPECT_DOUBLE_EQ(parse_quantity_as("1e31 mm", dim::length), 1e28);
  EXPECT_DOUBLE_EQ(parse_quantity_as("-1e30 m", dim::length), -1e30);
  EXPECT_DOUBLE_EQ(parse_quantity("1e30").value, 1e30);
  for (const char* text : {"1e308 in", "1e28 km^2", "-1e308 in/ms", "1e31", "1e300 cm/s"}) {
    SCOPED_TRACE(text);
    try {
      parse_quantity(text);
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("'") + text + "' is too large"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("1e+30"), std::string::npos) << e.what();
    }
  }
}

TEST(Units, TheExpectedDimensionIsNamedWithItsArticle) {
  auto message = [](const char* text, const Dim& d) {
    try {
      parse_quantity_as(text, d);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message("0", dim::acceleration), "'0' is a plain number, expected an acceleration (m/s^2)");
  EXPECT_EQ(message("2 s", dim::length), "'2 s' is a time (s), expected a length (m)");
  EXPECT_EQ(message("2 m", dim::area), "'2 m' is a length (m), expected an area (m^2)");
}

TEST(Units, WrongUnitsAreRejectedWithTheText) {
  try {
    parse_quantity_as("5.08 kg", dim::length);
    FAIL();
  } catch (const InputError& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("5.08 kg"), std::string::npos);
    EXPECT_NE(m.find("mass"), std::string::npos);
    EXPECT_NE(m.find("length"), std::string::npos);
  }
  EXPECT_THROW(parse_quantity_as("5.08", dim::length), InputError);
  EXPECT_THROW(parse_quantity_as("abc cm", dim::length), InputError);
  EXPECT_THROW(parse_quantity_as("5 furlongs", dim::length), InputError);
  EXPECT_THROW(parse_quantity_as("", dim::length), InputError);
  EXPECT_THROW(parse_quantity_as("1/0 cm", dim::length), InputError);
  EXPECT_THROW(parse_quantity_as("nan cm", dim::length), InputError);
  EXPECT_THROW(parse_quantity_as("2 cm^x", dim::area), InputError);
}

// A fraction in a message: a percentage while it reads as one, a plain ratio beyond 1000 % (never "5.76e+03 %").
// Found by fuzzing (fuzz_units): a power too long for an int ("m^24444444444") escaped as std::out_of_range, not
// as bad input; powers of powers could overflow the exponents.
TEST(Units, PowersOutOfRangeAreBadInput) {
  EXPECT_NEAR(parse_quantity("1 cm^2").value, 1e-4, 1e-18);
  EXPECT_EQ(parse_quantity("1 m^-12").dim, dim::length.pow(-12));
  for (const char* text : {"4444 s(m^24444444444", "1 m^24444444444", "1 m^13", "1 m^-13", "1 m^007",
                           "1 ((((m^12)^12)^12)^12)"}) {
    try {
      parse_quantity(text);
      ADD_FAILURE() << text << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  }
}

TEST(Share, PercentBelowAThousandPercentRatioBeyond) {
  EXPECT_EQ(polarcam::share(0.576), "57.6 %");
  EXPECT_EQ(polarcam::share(-0.2), "-20 %");
  EXPECT_EQ(polarcam::share(9.99), "999 %");
  EXPECT_EQ(polarcam::share(57.6), "57.6 times");
  EXPECT_EQ(polarcam::share(-12.0), "-12 times");
}

TEST(Share, PlainNumbersNeverInExponentForm) {
  EXPECT_EQ(polarcam::plain(0.0254), "0.0254");
  EXPECT_EQ(polarcam::plain(2909.92), "2910");
  EXPECT_EQ(polarcam::plain(55512.4), "55512");
  EXPECT_EQ(polarcam::share(29.1), "29.1 times");
  EXPECT_EQ(polarcam::share(2909.92), "2910 times");
}

// Error messages quote bytes of damaged inputs; on a terminal they must not move the cursor or change its state:
// control characters, DEL and malformed UTF-8 are escaped, well-formed UTF-8 is kept (found by a sweep of hostile
// inputs: a .thr of random bytes printed them raw).
TEST(Format, TerminalTextEscapesControlsAndMalformedUtf8) {
  EXPECT_EQ(terminal_text("rho 1.5 is outside 0..1"), "rho 1.5 is outside 0..1");
  EXPECT_EQ(terminal_text("a\x1b[2Jb"), "a\\x1b[2Jb");
  EXPECT_EQ(terminal_text("line\nnext\r\t\x7f"), "line\\x0anext\\x0d\\x09\\x7f");
  EXPECT_EQ(terminal_text("5 \xc2\xb5m \xe2\x80\x94 \xf0\x9f\x98\x80"), "5 \xc2\xb5m \xe2\x80\x94 \xf0\x9f\x98\x80");
  EXPECT_EQ(terminal_text("\xff"), "\\xff");
  EXPECT_EQ(terminal_text("x\xe2\x80"), "x\\xe2\\x80");          // cut short
  EXPECT_EQ(terminal_text("\xc0\x80"), "\\xc0\\x80");            // overlong
  EXPECT_EQ(terminal_text("\xed\xa0\x80"), "\\xed\\xa0\\x80");  // a surrogate
  EXPECT_EQ(terminal_text("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");  // beyond U+10FFFF
  EXPECT_EQ(terminal_text(std::string_view("a\0b", 3)), "a\\x00b");
}

}  // namespace tu_cam_test_units
