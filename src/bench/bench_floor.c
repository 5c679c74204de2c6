/* bench_floor.c — the floor under the node's CPU figure: a node that takes
 * the station's inputs as firmness_node does and does nothing with them
 * (the node targets, scripts/bench_node.sh --floor).
 *
 *   af_bench_floor [ROS remappings, e.g. __ns:=lane1 __name:=bench_floor]
 *
 * It makes the same ROS subscriptions through the same shim (src/shim):
 * force and audio as SignalChunk (queue 1000, deserialized into the C
 * structs), apple as AppleEstimate (queue 10), a TF listener, and /clock
 * when use_sim_time is set; its main thread spins as the node's does, with
 * the node's 50 ms timeout. Its callbacks only count. What it costs is what roscpp's receive
 * path costs on this machine for these messages, whatever the node does
 * with them. Prints the messages it took when ROS shuts it down (SIGINT).
 * Exit 0; 1 when ROS, a subscription or a spin fails (one line on stderr). */
#include <stdio.h>
#include <stdlib.h>

#include "closeout.h"
#include "af_msgs.h"
#include "af_ros.h"
#include "af_tf.h"

/* The node's spin timeout [s] and queue lengths (firmness_node.c, station.c). */
#define FLOOR_SPIN_TIMEOUT_S 0.05
#define FLOOR_CHUNK_QUEUE 1000
#define FLOOR_APPLE_QUEUE 10

static void count(const void *msg, void *user)
{
  (void)msg;
  ++*(unsigned long long *)user;
}

static af_status subscribe(af_ros *ros, unsigned long long n[3])
{
  static const char *const topic[3] = {"force", "audio", "apple"};
  af_ros_sub *sub; /* owned by the af_ros */
  af_status s = AF_OK;
  for (int k = 0; k < 3 && s == AF_OK; k++)
    s = af_ros_subscribe(ros, topic[k], k < 2 ? AF_MSG_SIGNAL_CHUNK : AF_MSG_APPLE_ESTIMATE,
                         k < 2 ? FLOOR_CHUNK_QUEUE : FLOOR_APPLE_QUEUE, count, &n[k], &sub);
  return s;
}

/* The TF listener and the subscriptions; *what names the part that failed. */
static af_status setup(af_ros *ros, af_tf **tf, unsigned long long n[3], const char **what)
{
  *what = "the TF listener";
  af_status s = af_tf_create(ros, tf);
  if (s != AF_OK)
    return s;
  *what = "the subscriptions";
  return subscribe(ros, n);
}

int main(int argc, char **argv)
{
  af_closeout_install("af_bench_floor");
  af_ros *ros = NULL;
  af_tf *tf = NULL;
  unsigned long long n[3] = {0, 0, 0}; /* force, audio, apple messages taken */
  const char *what = "ROS start-up";
  af_status s = af_ros_create(&argc, argv, "bench_floor", &ros);
  if (s == AF_OK)
    s = setup(ros, &tf, n, &what);
  if (s == AF_OK)
    what = "a spin";
  while (s == AF_OK && af_ros_ok(ros))
    s = af_ros_spin_once(ros, FLOOR_SPIN_TIMEOUT_S);
  if (s != AF_OK)
    fprintf(stderr, "af_bench_floor: %s failed: %s %s\n", what, af_strerror(s),
            ros ? af_ros_last_error(ros) : "");
  else
    printf("af_bench_floor: took %llu force, %llu audio and %llu apple messages\n", n[0], n[1],
           n[2]);
  af_tf_destroy(tf);
  af_ros_destroy(ros);
  return s == AF_OK ? EXIT_SUCCESS : EXIT_FAILURE;
}
