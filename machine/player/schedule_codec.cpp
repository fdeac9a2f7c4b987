// Queue items on the wire (docs/controller-protocol.md, "Step schedule", protocol version 2): the validity of a
// run, the per-axis prediction, and the byte encoding.
#include <algorithm>

#include "machine/player/int128.hpp"
#include "machine/player/schedule.hpp"

namespace polarcam {
namespace {

constexpr i128 kAddLimit = static_cast<i128>(1) << 62;

i128 floor_div(i128 a, i128 b) {  // b != 0
  i128 q = a / b;
  if ((a % b != 0) && ((a < 0) != (b < 0))) --q;
  return q;
}

int64_t wrap(i128 v) { return static_cast<int64_t>(static_cast<uint64_t>(static_cast<u128>(v))); }
int64_t wrap_add(int64_t a, int64_t b) {
  return static_cast<int64_t>(static_cast<uint64_t>(a) + static_cast<uint64_t>(b));
}

void put_varint(uint64_t v, std::string& out) {
  do {
    uint8_t b = v & 0x7f;
    v >>= 7;
    out.push_back(static_cast<char>(v ? (b | 0x80) : b));
  } while (v);
}
uint64_t zigzag(int64_t v) { return (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63); }
int64_t unzigzag(uint64_t v) { return static_cast<int64_t>(v >> 1) ^ -static_cast<int64_t>(v & 1); }
bool get_varint(const uint8_t* d, size_t len, size_t& pos, uint64_t& v) {
  v = 0;
  for (int shift = 0; shift < 64; shift += 7) {
    if (pos >= len) return false;
    uint8_t b = d[pos++];
    v |= static_cast<uint64_t>(b & 0x7f) << shift;
    if (!(b & 0x80)) return shift < 63 || (b & 0x7e) == 0;
  }
  return false;
}

// Even shift (at most 30) of the trailing zero bits of a difference: the wire sends it shifted right by that.
int wire_shift(uint64_t d) {
  int s = 0;
  while (d != 0 && s < 30 && (d & ((uint64_t{1} << (s + 2)) - 1)) == 0) s += 2;
  return s;
}

}  // namespace

bool run_is_valid(const QueueItem& r) {
  if (r.kind != ItemKind::run) return true;
  if (r.count == 0 || r.count > kMaxRunCount) return false;
  const i128 n = r.count, I = r.interval, A = r.add, B = r.add2;
  auto in_range = [](i128 iv) { return iv >= kOneTick && iv <= kMaxIntervalFx; };
  if (!in_range(static_cast<i128>(r.offset) + I)) return false;
  // adds A + (k-1) B for k = 1..n: linear, so both ends
  if (A < -kAddLimit || A > kAddLimit || A + (n - 1) * B < -kAddLimit || A + (n - 1) * B > kAddLimit) return false;
  if (B < -kAddLimit || B > kAddLimit) return false;
  if (n == 1) return true;
  // intervals q(j) = I + j A + C(j,2) B of steps j + 1, j = 1..n-1: a parabola, so both ends and its vertex
  auto q = [&](i128 j) { return I + j * A + j * (j - 1) / 2 * B; };
  if (!in_range(q(1)) || !in_range(q(n - 1))) return false;
  if (B != 0) {
    // q(j+1) - q(j) = A + j B changes sign near j = -A / B
    const i128 v = floor_div(-A, B);
    for (i128 j = v - 1; j <= v + 1; ++j)
      if (j >= 1 && j <= n - 1 && !in_range(q(j))) return false;
  }
  return true;
}

RunRef continuation(const QueueItem& r) {
  const i128 n = r.count, I = r.interval, A = r.add, B = r.add2;
  RunRef c;
  c.interval = wrap(I + n * A + n * (n - 1) / 2 * B);
  c.add = wrap(A + n * B);
  c.add2 = r.add2;
  return c;
}

void ItemCodec::encode(const QueueItem& it, std::string& out) {
  const int a = it.axis & 1;
  const uint8_t tag = static_cast<uint8_t>(a | (static_cast<int>(it.kind) << 1) | (it.dir > 0 ? 8 : 0));
  out.push_back(static_cast<char>(tag));
  if (it.kind == ItemKind::run) {
    // differences from the prediction, in wrapping 64-bit arithmetic (the decoder adds them back the same way)
    const uint64_t d[4] = {static_cast<uint64_t>(it.offset),
                           static_cast<uint64_t>(it.interval) - static_cast<uint64_t>(ref[a].interval),
                           static_cast<uint64_t>(it.add) - static_cast<uint64_t>(ref[a].add),
                           static_cast<uint64_t>(it.add2) - static_cast<uint64_t>(ref[a].add2)};
    int s[4];
    for (int i = 0; i < 4; ++i) s[i] = wire_shift(d[i]);
    put_varint(it.count, out);
    out.push_back(static_cast<char>((s[0] / 2) | ((s[1] / 2) << 4)));
    out.push_back(static_cast<char>((s[2] / 2) | ((s[3] / 2) << 4)));
    for (int i = 0; i < 4; ++i) put_varint(zigzag(static_cast<int64_t>(d[i]) >> s[i]), out);
    ref[a] = continuation(it);
  } else if (it.kind == ItemKind::wait) {
    put_varint(it.wait, out);
  }
}

bool ItemCodec::decode(const uint8_t* d, size_t len, size_t& pos, QueueItem& it) {
  size_t p = pos;
  if (p >= len) return false;
  const uint8_t tag = d[p++];
  if (tag & 0xf0) return false;
  const int kind = (tag >> 1) & 3;
  if (kind > 2) return false;
  QueueItem r;
  r.axis = tag & 1;
  r.kind = static_cast<ItemKind>(kind);
  r.dir = (tag & 8) ? 1 : -1;
  const int a = r.axis;
  if (r.kind == ItemKind::run) {
    uint64_t c;
    if (!get_varint(d, len, p, c) || c == 0 || c > kMaxRunCount || p + 2 > len) return false;
    const int s[4] = {2 * (d[p] & 15), 2 * (d[p] >> 4), 2 * (d[p + 1] & 15), 2 * (d[p + 1] >> 4)};
    p += 2;
    int64_t v[4];
    for (int i = 0; i < 4; ++i) {
      uint64_t z;
      if (s[i] > 30 || !get_varint(d, len, p, z)) return false;
      v[i] = static_cast<int64_t>(static_cast<uint64_t>(unzigzag(z)) << s[i]);
    }
    r.count = static_cast<uint32_t>(c);
    r.offset = v[0];
    r.interval = wrap_add(ref[a].interval, v[1]);
    r.add = wrap_add(ref[a].add, v[2]);
    r.add2 = wrap_add(ref[a].add2, v[3]);
    if (!run_is_valid(r)) return false;
    ref[a] = continuation(r);
  } else if (r.kind == ItemKind::wait) {
    if (!get_varint(d, len, p, r.wait)) return false;
  }
  it = r;
  pos = p;
  return true;
}

}  // namespace polarcam
