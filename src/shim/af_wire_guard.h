/* af_wire_guard.h — a cap on the node's array allocations, for the one
 * message buffer no hook of ours can see (wire_guard.cpp).
 *
 * roscpp's TCPROS subscriber reads a message's 4-byte length and then has
 * Connection::read allocate one buffer of that length (new uint8_t[len], up
 * to 1 GB) and fill it before any callback or deserializer sees a byte: a
 * 400 MB message cost the node 400 MB of RSS, though the wire cap then
 * refused it. firmness_node replaces operator new[] (wire_guard.cpp is
 * linked into the node only): above the cap it returns an inaccessible
 * reservation (PROT_NONE, MAP_NORESERVE: address space, no memory). The
 * kernel's recv() into it fails (EFAULT), roscpp drops that connection and
 * makes it again 0.1 s later; the message is never held, only counted here.
 * The messages a publisher sends meanwhile are lost to the node (a gap in
 * the stream's sample index, counted as such).
 *
 * Below the cap (and with the guard off, the default) new[] is malloc. The
 * cap must exceed every array the process allocates on purpose: the node
 * allows the largest message it can use and the largest it publishes
 * (station.c). */
#ifndef AF_WIRE_GUARD_H
#define AF_WIRE_GUARD_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Arrays of up to max_bytes are allowed; the cap only ever rises (0: no
 * effect). The first call turns the guard on. Thread-safe. */
void af_wire_guard_allow(size_t max_bytes);

typedef struct {
  size_t cap_bytes;             /* arrays above it are refused; 0: the guard is off */
  unsigned long long refused;   /* arrays refused (messages dropped), since start */
  size_t largest_refused_bytes; /* the longest of them */
} af_wire_guard_stats;

/* The figures so far. Thread-safe. In a binary without wire_guard.cpp
 * (every tool), not defined: only firmness_node links it. */
void af_wire_guard_get(af_wire_guard_stats *out);

#ifdef __cplusplus
}
#endif

#endif
