// wire.hpp — checks on serialized messages before roscpp deserializes them.
//
// roscpp's deserializer sizes a vector of a simple type from its 4-byte
// length prefix (std::vector::resize) before it checks that the message holds
// that many bytes (ros/serialization.h, VectorSerializer): 20 bytes claiming
// 10^9 float32 samples make it allocate and zero 4 GB. Strings are checked
// before they are built. So the only field of our inputs that can do this is
// SignalChunk.data; its layout is walked here, every length checked against
// the bytes that remain. Found by test/fuzz/fuzz_msgs.cpp.
#ifndef AF_SHIM_WIRE_HPP
#define AF_SHIM_WIRE_HPP

#include <cstddef>
#include <cstdint>
#include <string>

namespace af_shim
{

// Whether the n serialized bytes at p can be a SignalChunk whose every
// length prefix fits inside them (the message need not be complete: roscpp
// then throws, as usual). False when a prefix claims more than remains.
bool signal_chunk_plausible(const uint8_t *p, std::size_t n);

// What the n serialized bytes at p are as a SignalChunk, walked strictly
//: every field there (else cut, an empty message included), no
// length prefix past the end (else claims_too_much), data at most
// max_samples float32 (0: no cap; else oversized). *samples: data's stated
// length (0 when not reached); *why: one line naming the lengths.
enum class chunk_wire { ok, cut, claims_too_much, oversized };
chunk_wire signal_chunk_check(const uint8_t *p, std::size_t n, std::size_t max_samples,
                              uint32_t *samples, std::string *why);

// rosbag trusts the lengths a bag file states: a record header or a chunk
// that claims gigabytes makes it allocate them (rosbag::Bag::readHeader,
// the chunk's decompression buffer) before it finds the file shorter. This
// walks a bag's records (v2.0: header length, header fields, data length,
// and the records inside uncompressed chunks) by their lengths only, seeking
// over the data, and checks each against the file's size, a header against
// AF_BAG_HEADER_MAX and a chunk's stated size against AF_BAG_CHUNK_MAX.
// rosbag also reads a record wherever the index says one starts, without
// checking it lies inside its chunk: every index entry must point at a record
// of an uncompressed chunk (inside a compressed one, only within its size:
// its records are not walked), every chunk info at a chunk, the bag header's
// index position inside the file; and a connection record's data, itself a
// header that rosbag parses without checking its fields, is parsed here first
// (at most AF_BAG_HEADER_MAX). False with the first problem in why. Found by
// test/fuzz/fuzz_bag.c. *reindexable (when not null): the file is a bag of
// version 2.0 whose records or index are broken (cut short, never closed),
// which `rosbag reindex` may recover, as opposed to no bag at all.
constexpr std::size_t AF_BAG_HEADER_MAX = std::size_t(1) << 20; // 1 MiB
// rosbag holds a whole chunk in memory while its messages are read: 128 MiB
// keeps a tool within its 256 MiB peak RSS. rosbag's chunks are
// 768 KiB unless one message is longer; a chunk longer than a ring is
// refused message by message (af_bag_reader_limit).
constexpr std::size_t AF_BAG_CHUNK_MAX = std::size_t(1) << 27; // 128 MiB
bool bag_plausible(const char *path, std::string &why, bool *reindexable = nullptr);

} // namespace af_shim

#endif
