// wire.cpp — checks on serialized messages (see wire.hpp).
#include "wire.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

namespace af_shim
{

namespace
{

// A cursor over the serialized bytes: skip() and a length prefix, both
// false when the bytes run out.
struct cursor {
  const uint8_t *p;
  std::size_t left;

  bool skip(std::size_t k)
  {
    if (k > left)
      return false;
    p += k;
    left -= k;
    return true;
  }

  bool length(uint32_t &len)
  {
    if (left < 4)
      return false;
    std::memcpy(&len, p, 4); // little endian on the wire, as on every ROS host
    p += 4;
    left -= 4;
    return true;
  }
};

} // namespace

bool signal_chunk_plausible(const uint8_t *p, std::size_t n)
{
  cursor c{p, n};
  // Header: seq, stamp (sec, nsec), frame_id; then first_sample, sample_rate,
  // unit; then data. A message cut short anywhere before data is left to
  // roscpp (it throws): only a length that claims too much is refused.
  if (!c.skip(4 + 8))
    return true;
  uint32_t len;
  if (!c.length(len))
    return true;
  if (len > c.left)
    return false;
  c.skip(len);
  if (!c.skip(8 + 8))
    return true;
  if (!c.length(len))
    return true;
  if (len > c.left)
    return false;
  c.skip(len);
  if (!c.length(len))
    return true;
  return static_cast<std::size_t>(len) <= c.left / 4;
}

namespace
{

struct file_closer {
  void operator()(std::FILE *f) const
  {
    std::fclose(f);
  }
};

bool read_u32(std::FILE *f, uint32_t &v)
{
  unsigned char b[4];
  if (std::fread(b, 1, 4, f) != 4)
    return false;
  v = uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
  return true;
}

// One record header's fields (len, "name=value") that matter here.
struct record {
  int op = -1;
  std::string compression;
  uint64_t size = 0; // a chunk's uncompressed size
};

bool parse_header(const std::vector<unsigned char> &h, record &r, std::string &why)
{
  std::size_t at = 0;
  while (at < h.size()) {
    if (h.size() - at < 4) {
      why = "a header field is cut";
      return false;
    }
    uint32_t len = uint32_t(h[at]) | uint32_t(h[at + 1]) << 8 | uint32_t(h[at + 2]) << 16 |
                   uint32_t(h[at + 3]) << 24;
    at += 4;
    if (len > h.size() - at) {
      why = "a header field claims " + std::to_string(len) + " bytes, more than its header holds";
      return false;
    }
    const char *f = reinterpret_cast<const char *>(&h[at]);
    const char *eq = static_cast<const char *>(std::memchr(f, '=', len));
    if (eq != nullptr) {
      std::string name(f, eq - f), value(eq + 1, f + len);
      if (name == "op" && value.size() == 1)
        r.op = static_cast<unsigned char>(value[0]);
      else if (name == "compression")
        r.compression = value;
      else if (name == "size" && value.size() == 4)
        r.size = uint32_t(uint8_t(value[0])) | uint32_t(uint8_t(value[1])) << 8 |
                 uint32_t(uint8_t(value[2])) << 16 | uint32_t(uint8_t(value[3])) << 24;
    }
    at += len;
  }
  return true;
}

// The records in [pos, end) of f: each header and data inside the range.
// inner: the records of an uncompressed chunk (no chunks within).
bool walk(std::FILE *f, uint64_t pos, uint64_t end, bool inner, std::string &why)
{
  std::vector<unsigned char> h;
  while (pos < end) {
    uint32_t hlen, dlen;
    if (std::fseek(f, static_cast<long>(pos), SEEK_SET) != 0 || !read_u32(f, hlen)) {
      why = "cut at byte " + std::to_string(pos);
      return false;
    }
    if (hlen > AF_BAG_HEADER_MAX || hlen > end - pos - 4) {
      why = "the record at byte " + std::to_string(pos) + " claims a header of " +
            std::to_string(hlen) + " bytes, beyond " +
            (hlen > AF_BAG_HEADER_MAX ? std::string("the 1 MiB accepted") : "its end");
      return false;
    }
    h.resize(hlen);
    record r;
    if (std::fread(h.data(), 1, hlen, f) != hlen || !parse_header(h, r, why) ||
        !read_u32(f, dlen)) {
      if (why.empty())
        why = "the record at byte " + std::to_string(pos) + " is cut";
      else
        why = "the record at byte " + std::to_string(pos) + ": " + why;
      return false;
    }
    const uint64_t data = pos + 4 + hlen + 4;
    if (data > end || dlen > end - data) {
      why = "the record at byte " + std::to_string(pos) + " claims " + std::to_string(dlen) +
            " bytes of data, beyond " + (inner ? "its chunk" : "the end of the file");
      return false;
    }
    if (r.op == 0x05) { // a chunk
      if (inner) {
        why = "a chunk inside a chunk at byte " + std::to_string(pos);
        return false;
      }
      if (r.size > AF_BAG_CHUNK_MAX) {
        why = "the chunk at byte " + std::to_string(pos) + " claims " + std::to_string(r.size) +
              " bytes uncompressed, above the 256 MiB accepted";
        return false;
      }
      if (r.compression == "none" && r.size != dlen) {
        why = "the uncompressed chunk at byte " + std::to_string(pos) + " states " +
              std::to_string(r.size) + " bytes, its data has " + std::to_string(dlen);
        return false;
      }
      if (r.compression == "none" && !walk(f, data, data + dlen, true, why)) {
        why = "in the chunk at byte " + std::to_string(pos) + ": " + why;
        return false;
      }
    }
    pos = data + dlen;
  }
  return true;
}

} // namespace

bool bag_plausible(const char *path, std::string &why)
{
  std::unique_ptr<std::FILE, file_closer> f(std::fopen(path, "rb"));
  if (!f) {
    why = std::string("cannot be opened: ") + std::strerror(errno);
    return false;
  }
  static const char magic[] = "#ROSBAG V2.0\n";
  char head[sizeof magic - 1];
  if (std::fread(head, 1, sizeof head, f.get()) != sizeof head ||
      std::memcmp(head, magic, sizeof head) != 0) {
    why = "not a ROS bag of version 2.0";
    return false;
  }
  if (std::fseek(f.get(), 0, SEEK_END) != 0) {
    why = "cannot seek";
    return false;
  }
  long size = std::ftell(f.get());
  if (size < 0) {
    why = "cannot tell its size";
    return false;
  }
  return walk(f.get(), sizeof head, static_cast<uint64_t>(size), false, why);
}

} // namespace af_shim
