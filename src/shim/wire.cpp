// wire.cpp — checks on serialized messages (see wire.hpp).
#include "wire.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

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

chunk_wire signal_chunk_check(const uint8_t *p, std::size_t n, std::size_t max_samples,
                              uint32_t *samples, std::string *why)
{
  cursor c{p, n};
  uint32_t frame = 0, unit = 0, len = 0;
  *samples = 0;
  const std::string bytes = " of " + std::to_string(n) + " bytes";
  // seq, stamp, frame_id; first_sample, sample_rate; unit; data.
  bool whole = c.skip(4 + 8) && c.length(frame);
  if (whole && frame > c.left) {
    *why = "a SignalChunk" + bytes + " whose frame_id claims " + std::to_string(frame) + " bytes";
    return chunk_wire::claims_too_much;
  }
  whole = whole && c.skip(frame) && c.skip(8 + 8) && c.length(unit);
  if (whole && unit > c.left) {
    *why = "a SignalChunk" + bytes + " whose unit claims " + std::to_string(unit) + " bytes";
    return chunk_wire::claims_too_much;
  }
  whole = whole && c.skip(unit) && c.length(len);
  if (!whole) {
    *why = n == 0 ? std::string("an empty SignalChunk (0 bytes)")
                  : "a cut SignalChunk" + bytes + " (it ends before its data)";
    return chunk_wire::cut;
  }
  *samples = len;
  if (static_cast<std::size_t>(len) > c.left / 4) {
    *why = "a cut SignalChunk" + bytes + ": data claims " + std::to_string(len) +
           " samples, the message holds " + std::to_string(c.left / 4);
    return chunk_wire::claims_too_much;
  }
  if (max_samples > 0 && len > max_samples) {
    *why = "a SignalChunk of " + std::to_string(len) + " samples, above the cap of " +
           std::to_string(max_samples) + " (the ring; a longer chunk can never be used)";
    return chunk_wire::oversized;
  }
  return chunk_wire::ok;
}

namespace
{

// The little-endian uint32 at p (a bag's lengths and offsets).
uint32_t le32(const unsigned char *p)
{
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

// The bag's bytes by position, through one 64 KiB window read with pread:
// the walk visits a record's header, then the next record a little further
// on, so most reads are a copy from the window. (With stdio, every fseek
// dropped its buffer and cost an lseek and a read: 7 % of firmness_report's
// CPU on a 2000-strike bag.)
class bag_bytes
{
public:
  explicit bag_bytes(int fd) : fd_(fd), window_(std::size_t(1) << 16) {}
  ~bag_bytes()
  {
    if (fd_ >= 0)
      ::close(fd_);
  }
  bag_bytes(const bag_bytes &) = delete;
  bag_bytes &operator=(const bag_bytes &) = delete;

  // The n bytes at pos into out; false if the file ends first (or a read
  // fails).
  bool read(uint64_t pos, void *out, std::size_t n)
  {
    if (n == 0) // an empty header: out may be null (memcpy's arguments must not be)
      return true;
    if (n > window_.size())
      return read_all(pos, static_cast<unsigned char *>(out), n);
    if (pos < start_ || pos - start_ > held_ || n > held_ - (pos - start_)) {
      start_ = pos;
      held_ = 0;
      if (!read_all(pos, window_.data(), window_.size(), &held_) && held_ < n)
        return false;
    }
    std::memcpy(out, window_.data() + (pos - start_), n);
    return true;
  }

  bool read_u32(uint64_t pos, uint32_t &v)
  {
    unsigned char b[4];
    if (!read(pos, b, 4))
      return false;
    v = le32(b);
    return true;
  }

private:
  // pread until n bytes or the file's end; *got (when not null): how many.
  bool read_all(uint64_t pos, unsigned char *out, std::size_t n, std::size_t *got = nullptr)
  {
    std::size_t done = 0;
    while (done < n) {
      ssize_t k = ::pread(fd_, out + done, n - done, static_cast<off_t>(pos + done));
      if (k < 0 && errno == EINTR)
        continue;
      if (k <= 0)
        break;
      done += static_cast<std::size_t>(k);
    }
    if (got != nullptr)
      *got = done;
    return done == n;
  }

  int fd_;
  std::vector<unsigned char> window_;
  uint64_t start_ = 0;
  std::size_t held_ = 0;
};

// One record header's fields (len, "name=value") that matter here.
struct record {
  int op = -1;
  std::string compression;
  uint64_t size = 0;      // a chunk's uncompressed size
  uint64_t count = 0;     // index data: entries
  uint64_t chunk_pos = 0; // chunk info: where its chunk starts
  uint64_t index_pos = 0; // bag header: where the index starts
};

uint64_t little_endian(const std::string &v)
{
  uint64_t x = 0;
  for (std::size_t k = v.size(); k-- > 0;)
    x = x << 8 | uint8_t(v[k]);
  return x;
}

bool parse_header(const std::vector<unsigned char> &h, record &r, std::string &why)
{
  std::size_t at = 0;
  while (at < h.size()) {
    if (h.size() - at < 4) {
      why = "a header field is cut";
      return false;
    }
    uint32_t len = le32(&h[at]);
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
        r.size = little_endian(value);
      else if (name == "count" && value.size() == 4)
        r.count = little_endian(value);
      else if (name == "chunk_pos" && value.size() == 8)
        r.chunk_pos = little_endian(value);
      else if (name == "index_pos" && value.size() == 8)
        r.index_pos = little_endian(value);
    }
    at += len;
  }
  return true;
}

// What the walk learns: the chunks (where each starts, its uncompressed
// size, and for an uncompressed one where its records start, relative to its
// data), the last chunk seen (index data records follow their chunk), and
// the index's position from the bag header.
struct layout {
  struct chunk {
    uint64_t size = 0;
    bool compressed = false;
    std::vector<uint64_t> records;
  };
  std::vector<std::pair<uint64_t, chunk>> chunks; // in file order
  std::vector<uint64_t> chunk_infos;              // chunk_pos of each chunk info record
  std::vector<uint64_t> records;                  // where each top-level record starts
  uint64_t index_pos = 0;
};

// The offsets of an index data record's entries (time 8, offset 4 each):
// every one must start a record of its chunk (rosbag reads a header there
// without checking it lies inside the chunk).
bool check_index(bag_bytes &f, uint64_t data, uint32_t dlen, const record &r, const layout &l,
                 uint64_t pos, std::string &why)
{
  if (l.chunks.empty()) {
    why = "index data at byte " + std::to_string(pos) + " before any chunk";
    return false;
  }
  const layout::chunk &c = l.chunks.back().second;
  if (r.count > dlen / 12 || dlen != r.count * 12) {
    why = "index data at byte " + std::to_string(pos) + " states " + std::to_string(r.count) +
          " entries in " + std::to_string(dlen) + " bytes";
    return false;
  }
  for (uint64_t k = 0; k < r.count; k++) {
    unsigned char e[12];
    if (!f.read(data + 12 * k, e, 12)) {
      why = "index data at byte " + std::to_string(pos) + " is cut";
      return false;
    }
    const uint64_t off = le32(e + 8);
    const bool ok = c.compressed ? off + 8 <= c.size
                                 : std::binary_search(c.records.begin(), c.records.end(), off);
    if (!ok) {
      why = "index data at byte " + std::to_string(pos) + " points at byte " + std::to_string(off) +
            " of its chunk, where no record starts";
      return false;
    }
  }
  return true;
}

// A connection record's data is itself a header (topic, type, md5sum,
// definition), which rosbag parses without checking its fields' lengths
// against it (heap overflow in ros::Header::parse, found by fuzz_bag.c).
// h: scratch.
bool check_connection(bag_bytes &f, uint64_t data, uint32_t dlen, uint64_t pos,
                      std::vector<unsigned char> &h, std::string &why)
{
  if (dlen > AF_BAG_HEADER_MAX) {
    why = "the connection record at byte " + std::to_string(pos) + " has a header of " +
          std::to_string(dlen) + " bytes, above the 1 MiB accepted";
    return false;
  }
  h.resize(dlen);
  record ignored;
  if (!f.read(data, h.data(), dlen)) {
    why = "the connection record at byte " + std::to_string(pos) + " is cut";
    return false;
  }
  if (!parse_header(h, ignored, why)) {
    why = "the connection record at byte " + std::to_string(pos) + ": " + why;
    return false;
  }
  return true;
}

// The records in [pos, end) of f: each header and data inside the range;
// inner: the chunk being walked (its records noted; no chunk or index
// within), NULL at the top level.
bool walk(bag_bytes &f, uint64_t pos, uint64_t end, layout::chunk *inner, layout &l,
          std::string &why)
{
  std::vector<unsigned char> h;
  const uint64_t begin = pos;
  while (pos < end) {
    uint32_t hlen, dlen;
    if (!f.read_u32(pos, hlen)) {
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
    if (!f.read(pos + 4, h.data(), hlen) || !parse_header(h, r, why) ||
        !f.read_u32(pos + 4 + hlen, dlen)) {
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
    if (r.op == 0x07 && !check_connection(f, data, dlen, pos, h, why))
      return false;
    if (inner == nullptr)
      l.records.push_back(pos);
    if (inner != nullptr) {
      inner->records.push_back(pos - begin);
      if (r.op == 0x05 || r.op == 0x04 || r.op == 0x06 || r.op == 0x03) {
        why = "an index or chunk record inside a chunk at byte " + std::to_string(pos);
        return false;
      }
    } else if (r.op == 0x05) { // a chunk
      if (r.size > AF_BAG_CHUNK_MAX) {
        why = "the chunk at byte " + std::to_string(pos) + " claims " + std::to_string(r.size) +
              " bytes uncompressed, above the " + std::to_string(AF_BAG_CHUNK_MAX >> 20) +
              " MiB accepted (rosbag would hold it whole)";
        return false;
      }
      layout::chunk c;
      c.size = r.size;
      c.compressed = r.compression != "none";
      if (!c.compressed && r.size != dlen) {
        why = "the uncompressed chunk at byte " + std::to_string(pos) + " states " +
              std::to_string(r.size) + " bytes, its data has " + std::to_string(dlen);
        return false;
      }
      if (!c.compressed && !walk(f, data, data + dlen, &c, l, why)) {
        why = "in the chunk at byte " + std::to_string(pos) + ": " + why;
        return false;
      }
      l.chunks.emplace_back(pos, std::move(c));
    } else if (r.op == 0x04 && !check_index(f, data, dlen, r, l, pos, why)) {
      return false;
    } else if (r.op == 0x06) {
      l.chunk_infos.push_back(r.chunk_pos);
    } else if (r.op == 0x03) {
      l.index_pos = r.index_pos;
    }
    pos = data + dlen;
  }
  return true;
}

} // namespace

bool bag_plausible(const char *path, std::string &why, bool *reindexable)
{
  if (reindexable != nullptr)
    *reindexable = false;
  int fd = ::open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    why = std::string("cannot be opened: ") + std::strerror(errno);
    return false;
  }
  bag_bytes f(fd);
  static const char magic[] = "#ROSBAG V2.0\n";
  char head[sizeof magic - 1];
  if (!f.read(0, head, sizeof head) || std::memcmp(head, magic, sizeof head) != 0) {
    why = "not a ROS bag of version 2.0";
    return false;
  }
  if (reindexable != nullptr) // from here on, a bag whose layout is broken
    *reindexable = true;
  const off_t size = ::lseek(fd, 0, SEEK_END);
  if (size < 0) {
    why = std::string("cannot tell its size: ") + std::strerror(errno);
    return false;
  }
  layout l;
  if (!walk(f, sizeof head, static_cast<uint64_t>(size), nullptr, l, why))
    return false;
  // rosbag seeks to the index and to each chunk by these positions
  if (l.index_pos != static_cast<uint64_t>(size) &&
      !std::binary_search(l.records.begin(), l.records.end(), l.index_pos)) {
    why = "the bag header's index position " + std::to_string(l.index_pos) +
          " is not where a record starts";
    return false;
  }
  for (uint64_t p : l.chunk_infos) {
    bool found = false;
    for (const auto &c : l.chunks)
      found = found || c.first == p;
    if (!found) {
      why = "a chunk info points at byte " + std::to_string(p) + ", where no chunk starts";
      return false;
    }
  }
  return true;
}

} // namespace af_shim
