// bag_pool.hpp — rosbag::Bag objects kept for the process and reused by the
// bag reader (bag_read.cpp).
//
// Why: every rosbag::Bag constructs its own pluginlib ClassLoader for the
// encryptor plugin (package lookups through ament_index and rospack, the
// plugin XML parsed, the plugin instantiated) and unloads it again when it
// is destroyed: about 2 ms of a reader under ASan, 60 % of an input of
// test/fuzz/fuzz_bag.c, and 0.2 ms without sanitizers (a reader of a small
// bag costs 0.06 ms besides). A Bag closed and reset is as good as a new
// one: af_shim::bag_take gives one, af_shim::bag_give takes it back.
#ifndef AF_SHIM_BAG_POOL_HPP
#define AF_SHIM_BAG_POOL_HPP

#include <rosbag/bag.h>

namespace af_shim
{

// A Bag that is not open and in the state of a new one (no encryptor but
// rosbag's default, no decompressed chunk remembered). From the pool when
// it holds one, else new. Thread-safe; throws what rosbag::Bag's
// constructor throws, or std::bad_alloc.
rosbag::Bag *bag_take();

// Closes bag (rosbag errors while closing are swallowed: the reader has
// already reported what it read) and keeps it for the next bag_take; a bag
// that cannot be reset is deleted. NULL-safe, thread-safe, never throws.
void bag_give(rosbag::Bag *bag) noexcept;

} // namespace af_shim

#endif
