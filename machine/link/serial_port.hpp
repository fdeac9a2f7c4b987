#pragma once
// The host's serial port (libserial): baud rate, flow control, raw 8N1, timed reads and writes, reconnect.
#include <memory>
#include <string>

#include "machine/link/host_link.hpp"

namespace LibSerial {
class SerialPort;
}

namespace polarcam {

// Checks a baud rate against the standard rates; throws InputError naming --baud otherwise.
void check_baud(unsigned baud);

class SerialTransport : public Transport {
 public:
  // Opens the port; throws InputError (naming the port) when it cannot. flow: "none" or "hardware".
  SerialTransport(std::string port, unsigned baud, std::string flow);
  ~SerialTransport() override;
  bool write(const std::string& bytes, double timeout_s) override;
  std::string read(double timeout_s) override;
  double now() override;
  bool reconnect() override;
  std::string describe() const override;

 private:
  void open();
  std::string port_, flow_;
  unsigned baud_;
  std::unique_ptr<LibSerial::SerialPort> sp_;
  int fd_ = -1;
};

}  // namespace polarcam
