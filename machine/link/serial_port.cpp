#include "machine/link/serial_port.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <vector>
#include <libserial/SerialPort.h>

#include "cam/error.hpp"

namespace polarcam {
namespace {

struct Rate {
  unsigned baud;
  LibSerial::BaudRate code;
};
const Rate kRates[] = {
    {1200, LibSerial::BaudRate::BAUD_1200},     {2400, LibSerial::BaudRate::BAUD_2400},
    {4800, LibSerial::BaudRate::BAUD_4800},     {9600, LibSerial::BaudRate::BAUD_9600},
    {19200, LibSerial::BaudRate::BAUD_19200},   {38400, LibSerial::BaudRate::BAUD_38400},
    {57600, LibSerial::BaudRate::BAUD_57600},   {115200, LibSerial::BaudRate::BAUD_115200},
    {230400, LibSerial::BaudRate::BAUD_230400}, {460800, LibSerial::BaudRate::BAUD_460800},
    {921600, LibSerial::BaudRate::BAUD_921600}, {1000000, LibSerial::BaudRate::BAUD_1000000},
    {2000000, LibSerial::BaudRate::BAUD_2000000}};

std::string rate_list() {
  std::string s;
  for (const Rate& r : kRates) s += (s.empty() ? "" : ", ") + std::to_string(r.baud);
  return s;
}

}  // namespace

void check_baud(unsigned baud) {
  for (const Rate& r : kRates)
    if (r.baud == baud) return;
  throw InputError("--baud " + std::to_string(baud) + ": not a standard rate (" + rate_list() + ")");
}

SerialTransport::SerialTransport(std::string port, unsigned baud, std::string flow)
    : port_(std::move(port)), flow_(std::move(flow)), baud_(baud) {
  check_baud(baud);
  if (flow_ != "none" && flow_ != "hardware")
    throw InputError("--flow " + flow_ + ": must be none or hardware (software XON/XOFF cannot carry binary frames)");
  open();
}

namespace {

// Closes the port where its exception can be caught. A port that cannot even be closed (its device is gone) is
// let go without its destructor, which would close it again and throw out of a destructor.
void close_port(std::unique_ptr<LibSerial::SerialPort>& sp) {
  if (!sp) return;
  bool closed = true;
  try {
    if (sp->IsOpen()) sp->Close();
  } catch (...) {
    closed = false;
  }
  if (closed) {
    sp.reset();
    return;
  }
  // kept, never destroyed, where the program can still reach it (so that it is not a leak, only left open)
  static auto* abandoned = new std::vector<LibSerial::SerialPort*>();
  abandoned->push_back(sp.release());
}

}  // namespace

SerialTransport::~SerialTransport() { close_port(sp_); }

void SerialTransport::open() {
  // a missing path, or one that is not a terminal device (a file, /dev/null, a FIFO), is refused before libserial
  // sees it (its calls that only a terminal answers would fail half-way)
  const int probe = ::open(port_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (probe < 0)
    throw DeviceError("cannot open serial port " + port_ + " (" + std::strerror(errno) + "): check --port");
  const bool tty = ::isatty(probe) == 1;
  ::close(probe);
  if (!tty)
    throw DeviceError(port_ + " is not a serial port (not a terminal device): give the controller's port with --port, "
                      "e.g. /dev/ttyUSB0");
  sp_ = std::make_unique<LibSerial::SerialPort>();
  try {
    sp_->Open(port_);
    for (const Rate& r : kRates)
      if (r.baud == baud_) sp_->SetBaudRate(r.code);
    sp_->SetCharacterSize(LibSerial::CharacterSize::CHAR_SIZE_8);
    sp_->SetParity(LibSerial::Parity::PARITY_NONE);
    sp_->SetStopBits(LibSerial::StopBits::STOP_BITS_1);
    sp_->SetFlowControl(flow_ == "hardware" ? LibSerial::FlowControl::FLOW_CONTROL_HARDWARE
                                            : LibSerial::FlowControl::FLOW_CONTROL_NONE);
    fd_ = sp_->GetFileDescriptor();
  } catch (const std::exception& e) {
    close_port(sp_);
    fd_ = -1;
    throw DeviceError("cannot open serial port " + port_ + ": " + e.what() +
                      (errno ? std::string(" (") + std::strerror(errno) + ")" : ""));
  }
  // raw bytes, no line discipline, non-blocking I/O driven by poll()
  termios tio{};
  if (tcgetattr(fd_, &tio) == 0) {
    const speed_t sp = cfgetospeed(&tio);
    cfmakeraw(&tio);
    cfsetispeed(&tio, sp);
    cfsetospeed(&tio, sp);
    tio.c_cflag |= CLOCAL | CREAD;
    tcsetattr(fd_, TCSANOW, &tio);
  }
  fcntl(fd_, F_SETFL, fcntl(fd_, F_GETFL) | O_NONBLOCK);
  tcflush(fd_, TCIOFLUSH);
}

double SerialTransport::now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string SerialTransport::describe() const { return port_ + " at " + std::to_string(baud_) + " baud"; }

bool SerialTransport::write(const std::string& bytes, double timeout_s) {
  if (fd_ < 0) throw PlayError(describe() + ": the port is closed");
  size_t done = 0;
  const double until = now() + timeout_s;
  while (done < bytes.size()) {
    ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n > 0) {
      done += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EINTR) throw LinkLost(describe() + ": write failed (" + std::strerror(errno) + ")");
    const double left = until - now();
    if (left <= 0) return false;
    pollfd p{fd_, POLLOUT, 0};
    ::poll(&p, 1, static_cast<int>(left * 1000) + 1);
  }
  return true;
}

std::string SerialTransport::read(double timeout_s) {
  if (fd_ < 0) throw PlayError(describe() + ": the port is closed");
  pollfd p{fd_, POLLIN, 0};
  const int rc = ::poll(&p, 1, static_cast<int>(timeout_s * 1000));
  std::string out;
  if (rc <= 0) return out;
  if (p.revents & (POLLHUP | POLLERR | POLLNVAL)) {
    if (!(p.revents & POLLIN)) throw LinkLost(describe() + ": the port hung up (the controller is gone)");
  }
  char buf[4096];
  for (;;) {
    ssize_t n = ::read(fd_, buf, sizeof buf);
    if (n > 0) {
      out.append(buf, static_cast<size_t>(n));
      if (static_cast<size_t>(n) < sizeof buf) break;
      continue;
    }
    if (n == 0) break;
    if (errno == EAGAIN || errno == EINTR) break;
    throw LinkLost(describe() + ": read failed (" + std::strerror(errno) + ")");
  }
  return out;
}

bool SerialTransport::reconnect() {
  close_port(sp_);
  fd_ = -1;
  try {
    open();
    return true;
  } catch (const DeviceError&) {
    return false;
  }
}

}  // namespace polarcam
