// Signal files (time_s, then signal columns): a good file read back column by column; every kind of bad row
// refused with one InputError naming FILE:LINE and the column.
#include <gtest/gtest.h>

#include <string>

#include "cam/error.hpp"
#include "process/signal_file.hpp"

namespace polarcam::test {
namespace tu_process_test_signal_file {  // named: the test files compile together

TEST(SignalFile, ReadsColumnsCommentsAndCrlf) {
  const std::string text =
      "# a recording\r\ntime_s, current_A ,speed_rad_per_s\r\n0.000,1.5,10\r\n\r\n0.001,+1.75,-2e1\r\n0.002,2,0\r\n";
  const auto r = process::parse_signal_csv(text, "s.csv");
  ASSERT_EQ(r.names.size(), 2u);
  EXPECT_EQ(r.names[0], "current_A");
  EXPECT_EQ(r.names[1], "speed_rad_per_s");
  ASSERT_EQ(r.samples(), 3u);
  EXPECT_DOUBLE_EQ(r.period_s, 0.001);
  EXPECT_DOUBLE_EQ(r.start_s, 0.0);
  EXPECT_DOUBLE_EQ((*r.find("current_A"))[1], 1.75);
  EXPECT_DOUBLE_EQ((*r.find("speed_rad_per_s"))[1], -20.0);
  EXPECT_EQ(r.find("force_N"), nullptr);
}

TEST(SignalFile, FormatReadsBack) {
  process::SignalRecord r;
  r.start_s = 0.5;
  r.period_s = 0.002;
  r.names = {"force_N"};
  r.columns = {{1.0, -2.25, 3.125e-3, 0.0}};
  const auto back = process::parse_signal_csv(process::format_signal_csv(r), "x.csv");
  EXPECT_EQ(back.names, r.names);
  EXPECT_EQ(back.columns, r.columns);
  EXPECT_NEAR(back.period_s, 0.002, 1e-12);
  EXPECT_NEAR(back.start_s, 0.5, 1e-12);
}

// The error's place and a word of its message.
void expect_error(const std::string& text, const std::string& place, const std::string& word) {
  try {
    process::parse_signal_csv(text, "sig.csv");
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.place(), place) << e.what();
    EXPECT_NE(e.message().find(word), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
}

TEST(SignalFile, BadRowsNameFileLineAndColumn) {
  const std::string head = "time_s,force_N\n";
  expect_error(head + "0,1\n0.001,abc\n", "sig.csv:3", "force_N");
  expect_error(head + "0,1\n0.001,nan\n", "sig.csv:3", "finite");
  expect_error(head + "0,1\n0.001,1e999\n", "sig.csv:3", "finite");
  expect_error(head + "0,1\n0.001,-1e160\n", "sig.csv:3", "beyond 1e15");  // its square overflows in the RMS
  expect_error(head + "0,1\n0.001\n", "sig.csv:3", "fields");
  expect_error(head + "0,1\n0.001,2,3\n", "sig.csv:3", "fields");
  expect_error(head + "0,1\nx,2\n", "sig.csv:3", "time_s");
  expect_error(head + "0,1\n0,2\n", "sig.csv:3", "increase");
  expect_error(head + "0,1\n0.001,2\n0.003,2\n", "sig.csv:4", "evenly");
  expect_error(head + "0,1\n0.001,\n", "sig.csv:3", "force_N");
  expect_error("force_N,time_s\n1,0\n", "sig.csv:1", "time_s");
  expect_error("time_s\n0\n1\n", "sig.csv:1", "no signal column");
  expect_error("time_s,force N\n0,1\n", "sig.csv:1", "column name");
  expect_error("time_s,a,a\n0,1,1\n", "sig.csv:1", "twice");
  expect_error("# nothing\n", "sig.csv", "empty");
  expect_error(head + "0,1\n", "sig.csv", "two samples");
}

TEST(SignalFile, MissingFileIsAnInputError) {
  EXPECT_THROW(process::read_signal_csv("/nonexistent/signal.csv"), InputError);
}

}  // namespace tu_process_test_signal_file
}  // namespace polarcam::test
