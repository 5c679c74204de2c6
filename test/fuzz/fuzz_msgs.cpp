// fuzz_msgs.cpp — libFuzzer harness: the node's inputs as they come off the
// wire. The input is a sequence of records (1 byte: which message, 2 bytes:
// its length, then the serialized bytes), each deserialized by roscpp's own
// deserializer (ros::serialization, as a subscription does) into a
// SignalChunk (force or audio) or an AppleEstimate, converted by the shim
// (af_shim::from_ros, as its subscribers do), then into a core lane made
// from the table's defaults as the node would run them (af_lane_force /
// af_lane_audio / af_lane_apple; the node's conversion of the C mirrors to
// af_chunk / af_apple, src/node/lane_io.c and station.c, repeated here).
// Malformed bytes must be refused by the deserializer's checks (an
// exception), never crash, hang, allocate without bound or trip a
// sanitizer; what deserializes must go through the lane the same way.
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include <ros/serialization.h>

#include "convert.hpp"
#include "wire.hpp"

extern "C" {
#include "lane.h"
#include "lane_config.h"
#include "settings.h"
}

namespace
{

af_lane_config cfg;
bool cfg_made = false;
af_lane *lane = nullptr;

// A fresh lane for every input (the node's defaults, the shipped hammer,
// rings of 0.5 s instead of 2 s, the waits shortened to fit them). The configuration is a value the
// lane only reads (derived once: the same for every input); the lane itself, all its state, is made
// anew. Why 0.5 s: ASan maps, poisons and unmaps every block above 128 KiB; the two 2 s rings (400
// and 384 kB) took about half of each input's time (423-577 inputs/s against 892-1,079 with 0.5 s,
// seeds 1-3 alternated); the code the input drives is the same, and a chunk longer than the ring or
// a wrap comes 4 times sooner.
void make_lane()
{
  if (!cfg_made) {
    af_settings s;
    char err[512];
    af_settings_reset(&s);
    if (af_settings_set_arg(&s, "hammer_mass_kg=0.01", err, sizeof err) != AF_OK ||
        af_settings_set_arg(&s, "hammer_tip_radius_m=0", err, sizeof err) != AF_OK ||
        af_settings_set_arg(&s, "force_buffer_s=0.5", err, sizeof err) != AF_OK ||
        af_settings_set_arg(&s, "audio_buffer_s=0.5", err, sizeof err) != AF_OK ||
        // what a strike's audio must wait, within the 0.5 s ring (the
        // start-up check refuses a ring shorter than the waits)
        af_settings_set_arg(&s, "stream_stale_after_s=0.2", err, sizeof err) != AF_OK ||
        af_settings_set_arg(&s, "apple_wait_s=0.2", err, sizeof err) != AF_OK ||
        af_lane_config_derive(&s, &cfg, err, sizeof err) != AF_OK)
      std::abort();
    cfg_made = true;
  }
  const char *what = "";
  if (af_lane_create(&cfg, nullptr, nullptr, &lane, &what) != AF_OK)
    std::abort();
}

int64_t ns_of(const af_time &t)
{
  return static_cast<int64_t>(t.sec) * 1000000000 + t.nsec;
}

template <class M> bool deserialize(const uint8_t *p, size_t n, M &m)
{
  try {
    ros::serialization::IStream in(const_cast<uint8_t *>(p), static_cast<uint32_t>(n));
    ros::serialization::deserialize(in, m);
    return true;
  } catch (const ros::Exception &) {
    return false; // StreamOverrunException and the like: refused
  } catch (const std::bad_alloc &) {
    std::abort(); // a length prefix asked for more than the bytes hold
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  make_lane();
  int64_t now_ns = 0;
  for (int op = 0; op < 64 && size >= 3; op++) {
    const uint8_t kind = data[0] % 3;
    size_t n = static_cast<size_t>(data[1] | data[2] << 8);
    data += 3;
    size -= 3;
    if (n > size)
      n = size;
    // The shim's subscribers check a SignalChunk's bytes before roscpp
    // deserializes them (wire.hpp); an AppleEstimate has no vector.
    if (kind < 2 && !af_shim::signal_chunk_plausible(data, n)) {
      data += n;
      size -= n;
      continue;
    }
    if (kind < 2) {
      acoustic_firmness::SignalChunk m;
      if (deserialize(data, n, m)) {
        af_signal_chunk c;
        af_shim::from_ros(m, c);
        af_chunk k = {ns_of(c.header.stamp),
                      c.first_sample,
                      c.sample_rate_hz,
                      c.unit,
                      c.header.frame_id,
                      c.data,
                      c.n};
        now_ns = k.stamp_ns;
        if (kind == 0)
          (void)af_lane_force(lane, &k, now_ns, nullptr);
        else
          (void)af_lane_audio(lane, &k, now_ns, nullptr);
      }
    } else {
      acoustic_firmness::AppleEstimate m;
      if (deserialize(data, n, m)) {
        af_apple_estimate c;
        af_shim::from_ros(m, c);
        af_apple a;
        std::memset(&a, 0, sizeof a);
        a.apple_id = c.apple_id;
        a.stamp_ns = ns_of(c.header.stamp);
        a.mass_kg = c.mass_kg;
        a.equatorial_radius_m = c.equatorial_radius_m;
        a.strike_radius_m = c.strike_radius_m;
        a.stem_axis[0] = c.stem_axis.x;
        a.stem_axis[1] = c.stem_axis.y;
        a.stem_axis[2] = c.stem_axis.z;
        a.confidence = c.confidence;
        const af_prediction *pr = nullptr;
        (void)af_lane_apple(lane, &a, now_ns, &pr);
      }
    }
    data += n;
    size -= n;
  }
  af_lane_finish(lane);
  af_lane_destroy(lane);
  lane = nullptr;
  return 0;
}
