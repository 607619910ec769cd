/* hadal-ros2-lockstep-probe: a ROS 2 node's view of a lockstep hadald, written with Cyclone DDS (as under
 * rmw_cyclonedds_cpp) against the independently written ROS 2 types in ros2_types.idl. It commands the AUV
 * with std_msgs/Float64MultiArray on rt/<vehicle>/actuators/commands (as `ros2 topic pub` would) and steps
 * the server with hadal_msgs/StepRequest on rt/hadal/step_request, reading rt/hadal/step_reply and
 * rt/<vehicle>/odometry. Checks, each printed as "ok: ..." or "FAIL: ...":
 *   1. every step request is answered (same request_id), accepted, and sim time advances by steps x dt;
 *   2. the setpoints moved the vehicle forward (x grows by more than --min-advance metres), and the reply's
 *      ground truth (vehicle_names, poses) has the x its odometry has at the reply's sim time;
 *   3. a request with a wrong number of attached setpoints is refused with the server's reason;
 *   4. a reset request (reset = true, steps = 0) brings sim time back to 0 and the vehicle to its start.
 * usage: hadal-ros2-lockstep-probe [--domain-id N] [--vehicle auv] [--setpoints 0.8,0,0] [--requests 20]
 *                                  [--steps 50] [--step-size 0.002] [--min-advance 0.3]
 * Exit 0 when every check passed, 1 otherwise, 2 on a usage or DDS error. Discovery: loopback only, as
 * hadal-ros2-probe (set CYCLONEDDS_URI to override). */
#include <dds/dds.h>

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "probe_common.h"
#include "ros2_types.h"

#define MAX_SETPOINTS 16

/* The vehicle the probe drives, and its x in the last reply taken (NAN when the reply has none). */
static const char *g_vehicle = "auv";
static double g_reply_x = NAN;

/* Where a reply goes: the reply itself (its sequences are the reader's loan, not kept), its error, and
 * g_reply_x, the driven vehicle's x in it. */
struct reply_copy {
  hadal_msgs_msg_dds__StepReply_ *out;
  char *error;
  size_t error_size;
};

static void copy_reply(const hadal_msgs_msg_dds__StepReply_ *r, void *ctx) {
  struct reply_copy *c = ctx;
  *c->out = *r;
  snprintf(c->error, c->error_size, "%s", r->error ? r->error : "");
  g_reply_x = NAN;
  for (uint32_t v = 0; v < r->vehicle_names._length && 7 * v < r->poses._length; ++v) {
    if (strcmp(r->vehicle_names._buffer[v], g_vehicle) == 0) g_reply_x = r->poses._buffer[7 * v];
  }
}

/* The reply for `id` (or 20 s pass), in *out. */
static bool await_reply(dds_entity_t reader, uint64_t id, hadal_msgs_msg_dds__StepReply_ *out, char *error,
                        size_t error_size) {
  struct reply_copy c = {out, error, error_size};
  return await_step_reply(reader, id, copy_reply, &c);
}

/* The newest odometry sample with stamp >= t (waiting up to 20 s): its x and stamp. */
static bool odometry_at(dds_entity_t reader, double t, double *x, double *stamp) {
  for (int i = 0; i < 20000; ++i) {
    void *samples[1] = {NULL};
    dds_sample_info_t info;
    while (dds_take(reader, samples, &info, 1, 1) > 0) {
      const nav_msgs_msg_dds__Odometry_ *o = samples[0];
      if (info.valid_data) {
        *stamp = o->header.stamp.sec + 1e-9 * o->header.stamp.nanosec;
        *x = o->pose.pose.position.x;
      }
      dds_return_loan(reader, samples, 1);
      samples[0] = NULL;
    }
    if (*stamp >= t - 1e-9) return true;
    dds_sleepfor(DDS_MSECS(1));
  }
  return false;
}

int main(int argc, char **argv) {
  const char *env_domain = getenv("ROS_DOMAIN_ID");  /* default, as every Hadal tool: $ROS_DOMAIN_ID or 0 */
  int domain = (env_domain != NULL && *env_domain != '\0') ? atoi(env_domain) : 0;
  const char *vehicle = "auv";
  double setpoints[MAX_SETPOINTS] = {0.8, 0.0, 0.0};
  uint32_t n_setpoints = 3, steps = 50;
  int requests = 20;
  double dt = 0.002, min_advance = 0.3;
  for (int i = 1; i < argc; i += 2) {
    const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
    if (strcmp(a, "--domain") == 0) {
      fprintf(stderr, "hadal-ros2-lockstep-probe: --domain is now --domain-id\n");
      return 2;
    }
    if (v == NULL) {
      fprintf(stderr, "hadal-ros2-lockstep-probe: %s needs a value\n", a);
      return 2;
    }
    if (strcmp(a, "--domain-id") == 0) domain = atoi(v);
    else if (strcmp(a, "--vehicle") == 0) vehicle = g_vehicle = v;
    else if (strcmp(a, "--requests") == 0) requests = atoi(v);
    else if (strcmp(a, "--steps") == 0) steps = (uint32_t)atoi(v);
    else if (strcmp(a, "--step-size") == 0) dt = atof(v);
    else if (strcmp(a, "--min-advance") == 0) min_advance = atof(v);
    else if (strcmp(a, "--setpoints") == 0) {
      n_setpoints = 0;
      for (char *p = (char *)v; *p != '\0' && n_setpoints < MAX_SETPOINTS;) {
        char *end = NULL;
        setpoints[n_setpoints++] = strtod(p, &end);
        p = (*end == ',') ? end + 1 : end;
      }
    } else {
      fprintf(stderr, "hadal-ros2-lockstep-probe: unknown option %s\n", a);
      return 2;
    }
  }
  if (domain < 0 || domain > 232 || requests < 1 || steps < 1) {
    fprintf(stderr, "usage: hadal-ros2-lockstep-probe [--domain-id N] [--vehicle V] [--setpoints a,b,c] [--requests K] "
                    "[--steps S] [--step-size DT] [--min-advance M]\n");
    return 2;
  }
  configure_loopback();
  dds_entity_t pp = dds_create_participant((dds_domainid_t)domain, NULL, NULL);
  if (pp < 0) return 2;
  char setpoints_topic[256], odometry_topic[256];
  snprintf(setpoints_topic, sizeof(setpoints_topic), "rt/%s/actuators/commands", vehicle);
  snprintf(odometry_topic, sizeof(odometry_topic), "rt/%s/odometry", vehicle);
  dds_entity_t wr_request = endpoint(pp, &hadal_msgs_msg_dds__StepRequest__desc, "rt/hadal/step_request", true);
  dds_entity_t wr_setpoints = endpoint(pp, &std_msgs_msg_dds__Float64MultiArray__desc, setpoints_topic, true);
  dds_entity_t rd_reply = endpoint(pp, &hadal_msgs_msg_dds__StepReply__desc, "rt/hadal/step_reply", false);
  dds_entity_t rd_odom = endpoint(pp, &nav_msgs_msg_dds__Odometry__desc, odometry_topic, false);
  if (wr_request < 0 || wr_setpoints < 0 || rd_reply < 0 || rd_odom < 0) return 2;
  if (!wait_matched(wr_request, 20.0) || !wait_matched(wr_setpoints, 20.0)) {
    printf("FAIL: hadald's readers on rt/hadal/step_request and %s never matched\n", setpoints_topic);
    return 1;
  }
  /* Readers matched by hadald's writers before the first request (the writer side may lag the reader). */
  wait_subscribed(rd_reply, rd_odom, 20.0);

  uint64_t id = 1000;
  hadal_msgs_msg_dds__StepRequest_ request;
  memset(&request, 0, sizeof(request));
  std_msgs_msg_dds__Float64MultiArray_ command;
  memset(&command, 0, sizeof(command));
  command.data._buffer = setpoints;
  command.data._length = command.data._maximum = n_setpoints;
  hadal_msgs_msg_dds__StepReply_ reply;
  char error[512];

  /* Where the vehicle starts: the first odometry period (10 steps: 50 Hz at 500 Hz), from the reply's ground
   * truth. Not from odometry: its one sample may be written before hadald's writer has matched this
   * volatile reader, which then never receives it (seen under CI load). */
  request.request_id = ++id;
  request.steps = 10;
  dds_write(wr_request, &request);
  if (!await_reply(rd_reply, id, &reply, error, sizeof(error)) || isnan(g_reply_x)) {
    printf("FAIL: no reply to the first step request, or none with %s's ground truth\n", vehicle);
    return 1;
  }
  const double x0 = g_reply_x, t0 = reply.sim_time_s;

  /* 1 and 2: the setpoints on their own topic, the steps by request, as a ROS 2 node would. */
  bool answered = true, accepted = true, on_time = true;
  double t = t0;
  for (int k = 0; k < requests && answered; ++k) {
    dds_write(wr_setpoints, &command);  /* again each period: the server's command watchdog */
    dds_sleepfor(DDS_MSECS(5));         /* topics are not ordered with each other; the request comes after */
    request.request_id = ++id;
    request.steps = steps;
    dds_write(wr_request, &request);
    answered = await_reply(rd_reply, id, &reply, error, sizeof(error));
    accepted = accepted && answered && reply.accepted;
    on_time = on_time && answered && fabs(reply.sim_time_s - (t + steps * dt)) < 1e-9;
    t = reply.sim_time_s;
  }
  check(answered && accepted, "every step request answered and accepted", (double)requests, t);
  check(on_time, "sim time advanced by steps x dt per request", t - t0, requests * steps * dt);
  double x1 = 0.0, stamp = -1.0;
  const bool moved_known = odometry_at(rd_odom, t, &x1, &stamp);
  check(moved_known && x1 - x0 > min_advance, "the setpoints moved the vehicle forward [m]", x1 - x0, min_advance);
  check(moved_known && fabs(stamp - t) < 1e-9 && x1 == g_reply_x,
        "the reply carries the odometry's x at its sim time [m]", g_reply_x, x1);

  /* 3: a refused request, with the server's reason. */
  char *names[1] = {(char *)vehicle};
  uint32_t counts[1] = {n_setpoints - 1};
  request.request_id = ++id;
  request.steps = 1;
  request.vehicle_names._buffer = names;
  request.vehicle_names._length = request.vehicle_names._maximum = 1;
  request.setpoint_counts._buffer = counts;
  request.setpoint_counts._length = request.setpoint_counts._maximum = 1;
  request.setpoints._buffer = setpoints;
  request.setpoints._length = request.setpoints._maximum = n_setpoints - 1;
  dds_write(wr_request, &request);
  const bool refused = await_reply(rd_reply, id, &reply, error, sizeof(error)) && !reply.accepted &&
                       strstr(error, "setpoints") != NULL && fabs(reply.sim_time_s - t) < 1e-12;
  printf("   server's reason: %s\n", error);
  check(refused, "a wrong setpoint count is refused with a reason and steps nothing", reply.sim_time_s, t);

  /* 4: a reset request. */
  memset(&request.vehicle_names, 0, sizeof(request.vehicle_names));
  memset(&request.setpoint_counts, 0, sizeof(request.setpoint_counts));
  memset(&request.setpoints, 0, sizeof(request.setpoints));
  request.request_id = ++id;
  request.steps = 0;
  request.reset = true;
  dds_write(wr_request, &request);
  const bool reset = await_reply(rd_reply, id, &reply, error, sizeof(error)) && reply.accepted;
  double x_reset = 1e9;
  stamp = -1.0;
  /* The odometry published at the reset is the first with stamp 0 after the ones of the run before. */
  bool at_start = false;
  for (int i = 0; i < 20000 && reset && !at_start; ++i) {
    void *samples[1] = {NULL};
    dds_sample_info_t info;
    while (dds_take(rd_odom, samples, &info, 1, 1) > 0) {
      const nav_msgs_msg_dds__Odometry_ *o = samples[0];
      if (info.valid_data && o->header.stamp.sec == 0 && o->header.stamp.nanosec == 0) {
        x_reset = o->pose.pose.position.x;
        at_start = true;
      }
      dds_return_loan(rd_odom, samples, 1);
      samples[0] = NULL;
    }
    if (!at_start) dds_sleepfor(DDS_MSECS(1));
  }
  check(reset && reply.sim_time_s == 0.0, "a reset request brings sim time back to 0", reply.sim_time_s, 0.0);
  /* x0 was 20 ms after the start, at rest: the same place to well under a millimetre. */
  check(at_start && fabs(x_reset - x0) < 1e-3, "and the vehicle back to its start [m]", x_reset, x0);
  dds_delete(pp);
  return failures == 0 ? 0 : 1;
}
