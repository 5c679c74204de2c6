/* test_api.c — the parts of af_ros.h that need no ROS master: the time
 * conversions, and the API edge (NULL handles and arguments give AF_EINVAL
 * or a harmless no-op, never a crash). Node, parameters, topics and
 * diagnostics need a master and are covered by the node's rostests. */
#include <string.h>

#include "af_ros.h"
#include "af_test.h"

static void test_time(void)
{
  af_time t = af_time_from_s(1.5);
  AF_CHECK(t.sec == 1 && t.nsec == 500000000u);
  t = af_time_from_s(0.0);
  AF_CHECK(t.sec == 0 && t.nsec == 0);
  /* Rounding to the nearest ns, carrying into the seconds. */
  t = af_time_from_s(2.9999999999);
  AF_CHECK(t.sec == 3 && t.nsec == 0);
  t = af_time_from_s(1700000000.25);
  AF_CHECK(t.sec == 1700000000u && t.nsec == 250000000u);
  /* Outside ROS time: the nearest end, no exception, no wrap-around. */
  t = af_time_from_s(-1.0);
  AF_CHECK(t.sec == 0 && t.nsec == 0);
  t = af_time_from_s(NAN);
  AF_CHECK(t.sec == 0 && t.nsec == 0);
  t = af_time_from_s(1e12);
  AF_CHECK(t.sec == 4294967295u && t.nsec == 999999999u);

  af_time u = {12, 345000000u};
  AF_CHECK_ABS(af_time_to_s(u), 12.345, 1e-9); /* [s] */
  u.sec = 1700000000u;
  u.nsec = 1;
  AF_CHECK_ABS(af_time_to_s(u) - 1700000000.0, 1e-9, 1e-9);
  /* Round trip at 1 us (double has ~0.2 us at 1.7e9 s). */
  AF_CHECK_ABS(af_time_to_s(af_time_from_s(1700000000.123456)), 1700000000.123456, 1e-6);

  /* Before ros::init there is no clock: zero, with the reason kept. */
  af_time now = af_ros_now(NULL);
  AF_CHECK(now.sec == 0 && now.nsec == 0);
  AF_CHECK(af_ros_last_error(NULL)[0] != '\0');
}

static void test_null_handles(void)
{
  af_ros *r = (af_ros *)&r;
  int argc = 0;
  AF_CHECK_STATUS(af_ros_create(&argc, NULL, "", &r), AF_EINVAL);
  AF_CHECK(r == NULL);
  AF_CHECK(strstr(af_ros_last_error(NULL), "node_name") != NULL);
  AF_CHECK_STATUS(af_ros_create(&argc, NULL, "n", NULL), AF_EINVAL);
  AF_CHECK_STATUS(af_ros_create(NULL, NULL, "n", &r), AF_EINVAL);
  af_ros_destroy(NULL);

  AF_CHECK(af_ros_last_error(NULL) != NULL);
  AF_CHECK(!af_ros_ok(NULL));
  AF_CHECK(strcmp(af_ros_node_name(NULL), "") == 0);
  AF_CHECK_STATUS(af_ros_spin_once(NULL, 0.01), AF_EINVAL);

  double d;
  int i;
  bool b;
  char buf[8];
  AF_CHECK_STATUS(af_ros_param_double(NULL, "x", &d), AF_EINVAL);
  AF_CHECK_STATUS(af_ros_param_int(NULL, "x", &i), AF_EINVAL);
  AF_CHECK_STATUS(af_ros_param_bool(NULL, "x", &b), AF_EINVAL);
  AF_CHECK_STATUS(af_ros_param_string(NULL, "x", buf, sizeof buf), AF_EINVAL);
  AF_CHECK_STATUS(af_ros_param_string_global(NULL, "x", buf, sizeof buf), AF_EINVAL);
  AF_CHECK_STATUS(af_ros_param_string(NULL, "x", NULL, 0), AF_EINVAL);
  AF_CHECK(af_ros_param_string_bytes(NULL, "x", true) == 0);

  af_ros_pub *p = (af_ros_pub *)&p;
  af_ros_sub *s = (af_ros_sub *)&s;
  AF_CHECK_STATUS(af_ros_advertise(NULL, "t", AF_MSG_RELIABILITY, 1, false, &p), AF_EINVAL);
  AF_CHECK(p == NULL);
  AF_CHECK_STATUS(af_ros_publish(NULL, &d), AF_EINVAL);
  AF_CHECK(af_ros_pub_subscribers(NULL) == 0);
  AF_CHECK_STATUS(af_ros_subscribe(NULL, "t", AF_MSG_SIGNAL_CHUNK, 1, NULL, NULL, &s), AF_EINVAL);
  AF_CHECK(s == NULL);

  af_ros_diag *g = (af_ros_diag *)&g;
  AF_CHECK_STATUS(af_ros_diag_create(NULL, "lane1", &g), AF_EINVAL);
  AF_CHECK(g == NULL);
  AF_CHECK_STATUS(af_ros_diag_add_task(NULL, "task", NULL, NULL), AF_EINVAL);
  af_ros_diag_update(NULL);
  af_ros_diag_force_update(NULL);
  af_diag_summary(NULL, AF_DIAG_OK, "ok");
  af_diag_add(NULL, "key", "%d", 1);
}

int main(void)
{
  test_time();
  test_null_handles();
  return af_test_summary("test_api");
}
