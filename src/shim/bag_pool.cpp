// bag_pool.cpp — reused rosbag::Bag objects (bag_pool.hpp).
#include "bag_pool.hpp"

#include <mutex>
#include <vector>

namespace
{

// The pool: leaked on purpose, so that no Bag (and its ClassLoader) is
// destroyed during static destruction after class_loader's own statics.
struct bag_pool {
  std::mutex lock;
  std::vector<rosbag::Bag *> free;
};

bag_pool &pool()
{
  static bag_pool *p = new bag_pool;
  return *p;
}

// Bags kept at most: one per reader open at once (firmness_report's
// workers); more are deleted when given back.
constexpr std::size_t AF_BAG_POOL_MAX = 16;

} // namespace

namespace af_shim
{

rosbag::Bag *bag_take()
{
  {
    std::lock_guard<std::mutex> hold(pool().lock);
    if (!pool().free.empty()) {
      rosbag::Bag *b = pool().free.back();
      pool().free.pop_back();
      return b;
    }
  }
  return new rosbag::Bag;
}

void bag_give(rosbag::Bag *bag) noexcept
{
  if (bag == nullptr)
    return;
  try {
    // rosbag 1.15's close() of an open bag ends in Bag::init(), as its
    // constructor does: every field a read set (the decompressed chunk's
    // offset, the encryptor the bag's header named) is a new Bag's again
    // (checked by test/shim/test_bag_reuse.c).
    bag->close();
    std::lock_guard<std::mutex> hold(pool().lock);
    if (pool().free.size() < AF_BAG_POOL_MAX) {
      pool().free.push_back(bag);
      return;
    }
  } catch (...) {
    // Not reset (or no room to keep it): not reused.
  }
  try {
    delete bag;
  } catch (...) {
    // rosbag's destructor closes again; nothing is open any more.
  }
}

} // namespace af_shim
