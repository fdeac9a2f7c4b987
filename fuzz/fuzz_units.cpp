// Quantities with units (cam/units.hpp): parse_quantity, parse_quantity_as (a length, a speed, an angle, which
// also takes a plain number) and eval_number on the text.
#include "cam/units.hpp"
#include "fuzz/fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace polarcam;
  const std::string_view text = fuzz::as_text(data, size);
  fuzz::expect_typed([&] { describe(parse_quantity(text).dim); });
  fuzz::expect_typed([&] { parse_quantity_as(text, dim::length); });
  fuzz::expect_typed([&] { parse_quantity_as(text, dim::speed); });
  fuzz::expect_typed([&] { parse_quantity_as(text, dim::angle); });
  fuzz::expect_typed([&] { eval_number(text); });
  return 0;
}
