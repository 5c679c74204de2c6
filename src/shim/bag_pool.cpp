// bag_pool.cpp — reused rosbag::Bag objects (bag_pool.hpp).
#include "bag_pool.hpp"

#include <dlfcn.h>

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

// rosbag's encryptor plugins (the soname of rosbag_storage's plugin library):
// loaded by the first Bag, kept mapped for the process. pluginlib unloads
// the library whenever no ClassLoader holds it (a Bag destroyed, and inside
// each lookup of the library's path): every unload and reload costs a
// mapping and its relocations, and the AES encryptor's library keeps
// strdup'd strings that LeakSanitizer reports as lost once it is unmapped.
constexpr const char *AF_BAG_ENCRYPTOR_LIBRARY = "librosbag_default_encryption_plugins.so";

// Marks the already loaded library RTLD_NODELETE; nothing when it is not
// loaded under that name (another rosbag build): as before, then.
void keep_encryptor_library()
{
  static std::once_flag once;
  std::call_once(once, [] {
    (void)dlopen(AF_BAG_ENCRYPTOR_LIBRARY, RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE);
  });
}

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
  rosbag::Bag *b = new rosbag::Bag;
  keep_encryptor_library();
  return b;
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
