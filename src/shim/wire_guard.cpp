// wire_guard.cpp — operator new[] with a cap (af_wire_guard.h). Linked into
// firmness_node only (CMakeLists.txt): replacing the global allocation
// functions is a choice for a whole program, not for a library.
#include "af_wire_guard.h"

#include <sys/mman.h>

#include <atomic>
#include <cstdlib>
#include <mutex>
#include <new>

namespace
{

// Reservations not yet deleted: one per connection reading a refused
// message, so a few at most. When all are taken, new[] falls back to malloc
// (the message is then held, as without the guard).
constexpr int reservation_slots = 32;

struct reservation {
  void *p;
  std::size_t n; // bytes
};

std::atomic<std::size_t> cap{0}; // bytes; 0: the guard is off
std::atomic<unsigned long long> refused{0};
std::atomic<std::size_t> largest{0};
std::atomic<int> live{0}; // slots in use: delete[] looks only when > 0
std::mutex table_lock;    // guards table
reservation table[reservation_slots];

// Address space only: PROT_NONE pages are never backed by memory, and any
// access to them (the kernel's copy into them included) fails.
void *reserve(std::size_t n)
{
  void *p = mmap(nullptr, n, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (p == MAP_FAILED)
    return nullptr;
  std::lock_guard<std::mutex> g(table_lock);
  for (reservation &r : table)
    if (r.p == nullptr) {
      r = reservation{p, n};
      live.fetch_add(1);
      return p;
    }
  munmap(p, n);
  return nullptr;
}

bool release(void *p)
{
  if (live.load() == 0)
    return false;
  std::lock_guard<std::mutex> g(table_lock);
  for (reservation &r : table)
    if (r.p == p) {
      munmap(r.p, r.n);
      r = reservation{nullptr, 0};
      live.fetch_sub(1);
      return true;
    }
  return false;
}

// a = max(a, v), atomically.
void raise_to(std::atomic<std::size_t> &a, std::size_t v)
{
  std::size_t now = a.load();
  while (v > now && !a.compare_exchange_weak(now, v)) {
  }
}

} // namespace

void *operator new[](std::size_t n)
{
  const std::size_t c = cap.load(std::memory_order_relaxed);
  if (c != 0 && n > c) {
    if (void *p = reserve(n)) {
      refused.fetch_add(1);
      raise_to(largest, n);
      return p;
    }
  }
  void *p = std::malloc(n != 0 ? n : 1);
  if (p == nullptr)
    throw std::bad_alloc();
  return p;
}

void operator delete[](void *p) noexcept
{
  if (p != nullptr && !release(p))
    std::free(p);
}

void operator delete[](void *p, std::size_t) noexcept
{
  operator delete[](p);
}

extern "C" {

void af_wire_guard_allow(std::size_t max_bytes)
{
  raise_to(cap, max_bytes);
}

void af_wire_guard_get(af_wire_guard_stats *out)
{
  out->cap_bytes = cap.load();
  out->refused = refused.load();
  out->largest_refused_bytes = largest.load();
}

} // extern "C"
