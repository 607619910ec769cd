/* hadal-ros2-joint-probe: a ROS 2 node's view of an articulated vehicle in a lockstep hadald, written with
 * Cyclone DDS (as under rmw_cyclonedds_cpp) against the independently written ROS 2 types in ros2_types.idl.
 * It commands a joint controller with std_msgs/Float64MultiArray on rt/<vehicle>/<controller>/commands (as
 * `ros2 topic pub` would, and attached to the step request as hadal's clients do), steps the server with
 * hadal_msgs/StepRequest, and reads sensor_msgs/JointState on rt/<vehicle>/joint_states. Checks, each printed
 * as "ok: ..." or "FAIL: ...":
 *   1. the step request carrying the joint command is accepted;
 *   2. JointState names the expected joints, with as many positions, velocities and efforts, all finite, and
 *      the commanded joint's effort is the commanded value (an effort controller), at the reply's sim time;
 *   3. a command for a joint controller the vehicle does not have is refused with the server's reason and
 *      steps nothing;
 *   4. a trajectory_msgs/JointTrajectory published on rt/<vehicle>/<position group>/joint_trajectory (as
 *      MoveIt hands one to ros2_control's joint_trajectory_controller), stamped ahead in sim time, brings
 *      its joint to the waypoint within 3 degrees;
 *   5. the force/torque sensor's geometry_msgs/WrenchStamped on rt/<vehicle>/<sensor> comes at the reply's
 *      sim time, in the sensor's frame, finite, its force between 1 and 100 N (the forearm's wet weight
 *      and swing).
 * usage: hadal-ros2-joint-probe [--domain-id N] [--vehicle arm] [--controller forearm_effort] [--joint 1]
 *                               [--joints 2] [--effort 0.5] [--position-group shoulder_position]
 *                               [--position-joint shoulder] [--position-index 0] [--wrench-sensor elbow_ft]
 * Exit 0 when every check passed, 1 otherwise, 2 on a usage or DDS error. Discovery: loopback only (set
 * CYCLONEDDS_URI to override). */
#include <dds/dds.h>

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "probe_common.h"
#include "ros2_types.h"

/* What a reply leaves: accepted, sim time and error. */
struct reply_copy {
  bool *accepted;
  double *sim_time;
  char *error;
  size_t error_size;
};

static void copy_reply(const hadal_msgs_msg_dds__StepReply_ *r, void *ctx) {
  struct reply_copy *c = ctx;
  *c->accepted = r->accepted;
  *c->sim_time = r->sim_time_s;
  snprintf(c->error, c->error_size, "%s", r->error ? r->error : "");
}

/* The reply for `id` (or 20 s pass): accepted, sim time and error copied out. */
static bool await_reply(dds_entity_t reader, uint64_t id, bool *accepted, double *sim_time, char *error,
                        size_t error_size) {
  struct reply_copy c = {accepted, sim_time, error, error_size};
  return await_step_reply(reader, id, copy_reply, &c);
}

int main(int argc, char **argv) {
  const char *env_domain = getenv("ROS_DOMAIN_ID");
  int domain = (env_domain != NULL && *env_domain != '\0') ? atoi(env_domain) : 0;
  const char *vehicle = "arm", *controller = "forearm_effort";
  int joint = 1, joints = 2;
  double effort = 0.5;
  const char *group = "shoulder_position", *group_joint = "shoulder", *wrench_sensor = "elbow_ft";
  int group_index = 0;
  for (int i = 1; i < argc; i += 2) {
    const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
    if (v == NULL) {
      fprintf(stderr, "hadal-ros2-joint-probe: %s needs a value\n", a);
      return 2;
    }
    if (strcmp(a, "--domain-id") == 0) domain = atoi(v);
    else if (strcmp(a, "--vehicle") == 0) vehicle = v;
    else if (strcmp(a, "--controller") == 0) controller = v;
    else if (strcmp(a, "--joint") == 0) joint = atoi(v);
    else if (strcmp(a, "--joints") == 0) joints = atoi(v);
    else if (strcmp(a, "--effort") == 0) effort = atof(v);
    else if (strcmp(a, "--position-group") == 0) group = v;
    else if (strcmp(a, "--position-joint") == 0) group_joint = v;
    else if (strcmp(a, "--position-index") == 0) group_index = atoi(v);
    else if (strcmp(a, "--wrench-sensor") == 0) wrench_sensor = v;
    else {
      fprintf(stderr, "hadal-ros2-joint-probe: unknown option %s\n", a);
      return 2;
    }
  }
  if (domain < 0 || domain > 232 || joints < 1 || joint < 0 || joint >= joints || group_index < 0 ||
      group_index >= joints) {
    fprintf(stderr, "usage: hadal-ros2-joint-probe [--domain-id N] [--vehicle V] [--controller C] [--joint K] "
                    "[--joints N] [--effort E]\n");
    return 2;
  }
  configure_loopback();
  dds_entity_t pp = dds_create_participant((dds_domainid_t)domain, NULL, NULL);
  if (pp < 0) return 2;
  char command_topic[256], joints_topic[256], trajectory_topic[256], wrench_topic[256], wrench_frame[256];
  snprintf(wrench_topic, sizeof(wrench_topic), "rt/%s/%s", vehicle, wrench_sensor);
  snprintf(wrench_frame, sizeof(wrench_frame), "%s/%s", vehicle, wrench_sensor);
  snprintf(command_topic, sizeof(command_topic), "rt/%s/%s/commands", vehicle, controller);
  snprintf(trajectory_topic, sizeof(trajectory_topic), "rt/%s/%s/joint_trajectory", vehicle, group);
  snprintf(joints_topic, sizeof(joints_topic), "rt/%s/joint_states", vehicle);
  dds_entity_t wr_request = endpoint(pp, &hadal_msgs_msg_dds__StepRequest__desc, "rt/hadal/step_request", true);
  dds_entity_t wr_command = endpoint(pp, &std_msgs_msg_dds__Float64MultiArray__desc, command_topic, true);
  dds_entity_t rd_reply = endpoint(pp, &hadal_msgs_msg_dds__StepReply__desc, "rt/hadal/step_reply", false);
  dds_entity_t rd_joints = endpoint(pp, &sensor_msgs_msg_dds__JointState__desc, joints_topic, false);
  dds_entity_t wr_trajectory =
      endpoint(pp, &trajectory_msgs_msg_dds__JointTrajectory__desc, trajectory_topic, true);
  dds_entity_t rd_wrench = endpoint(pp, &geometry_msgs_msg_dds__WrenchStamped__desc, wrench_topic, false);
  if (wr_request < 0 || wr_command < 0 || rd_reply < 0 || rd_joints < 0 || wr_trajectory < 0 || rd_wrench < 0) {
    return 2;
  }
  if (!wait_matched(wr_request, 20.0) || !wait_matched(wr_command, 20.0) || !wait_matched(wr_trajectory, 20.0)) {
    printf("FAIL: hadald's readers on rt/hadal/step_request, %s and %s never matched\n", command_topic,
           trajectory_topic);
    return 1;
  }
  wait_subscribed(rd_reply, rd_joints, 20.0);
  wait_subscribed(rd_reply, rd_wrench, 20.0);

  /* 1: the command on its topic and attached to the request. */
  double value = effort;
  std_msgs_msg_dds__Float64MultiArray_ command;
  memset(&command, 0, sizeof(command));
  command.data._buffer = &value;
  command.data._length = command.data._maximum = 1;
  dds_write(wr_command, &command);
  char *vehicles[1] = {(char *)vehicle};
  char *controllers[1] = {(char *)controller};
  uint32_t counts[1] = {1};
  hadal_msgs_msg_dds__StepRequest_ request;
  memset(&request, 0, sizeof(request));
  request.request_id = 1;
  request.steps = 50;
  request.joint_command_vehicles._buffer = vehicles;
  request.joint_command_vehicles._length = request.joint_command_vehicles._maximum = 1;
  request.joint_command_controllers._buffer = controllers;
  request.joint_command_controllers._length = request.joint_command_controllers._maximum = 1;
  request.joint_command_counts._buffer = counts;
  request.joint_command_counts._length = request.joint_command_counts._maximum = 1;
  request.joint_commands._buffer = &value;
  request.joint_commands._length = request.joint_commands._maximum = 1;
  dds_write(wr_request, &request);
  bool accepted = false;
  double t = -1.0;
  char error[512];
  const bool answered = await_reply(rd_reply, 1, &accepted, &t, error, sizeof(error));
  check(answered && accepted, "the step request with a joint command is accepted", t, 0.1);

  /* 2: the newest JointState at the reply's sim time. */
  bool found = false, names_ok = false, finite = true;
  uint32_t n_names = 0, n_position = 0, n_velocity = 0, n_effort = 0;
  double echoed = NAN, stamp = -1.0;
  for (int i = 0; i < 20000 && answered && !(stamp >= t - 1e-9); ++i) {
    void *samples[1] = {NULL};
    dds_sample_info_t info;
    while (dds_take(rd_joints, samples, &info, 1, 1) > 0) {
      const sensor_msgs_msg_dds__JointState_ *m = samples[0];
      if (info.valid_data) {
        found = true;
        stamp = m->header.stamp.sec + 1e-9 * m->header.stamp.nanosec;
        n_names = m->name._length;
        n_position = m->position._length;
        n_velocity = m->velocity._length;
        n_effort = m->effort._length;
        names_ok = n_names == (uint32_t)joints;
        finite = true;
        for (uint32_t k = 0; k < n_position && k < n_velocity; ++k) {
          finite = finite && isfinite(m->position._buffer[k]) && isfinite(m->velocity._buffer[k]);
        }
        echoed = (uint32_t)joint < n_effort ? m->effort._buffer[joint] : NAN;
        if (names_ok) printf("   joints: %s, %s\n", m->name._buffer[0], n_names > 1 ? m->name._buffer[1] : "");
      }
      dds_return_loan(rd_joints, samples, 1);
    }
    dds_sleepfor(DDS_MSECS(1));
  }
  check(found && fabs(stamp - t) < 1e-9, "a JointState at the reply's sim time [s]", stamp, t);
  check(names_ok && n_position == n_names && n_velocity == n_names && n_effort == n_names && finite,
        "JointState names every joint, with as many finite positions, velocities and efforts", n_names, joints);
  check(echoed == effort, "the commanded joint's effort is the command [N m]", echoed, effort);

  /* 3: a controller the vehicle does not have. */
  controllers[0] = "no_such_controller";
  request.request_id = 2;
  request.steps = 1;
  dds_write(wr_request, &request);
  double t_refused = -1.0;
  const bool refused = await_reply(rd_reply, 2, &accepted, &t_refused, error, sizeof(error)) && !accepted &&
                       strstr(error, "no joint controller 'no_such_controller'") != NULL &&
                       fabs(t_refused - t) < 1e-12;
  printf("   server's reason: %s\n", error);
  check(refused, "a command for an unknown joint controller is refused and steps nothing", t_refused, t);

  /* 4: a trajectory on its topic, stamped 0.1 s ahead (so it does not matter at which step it arrives), to
   * 0.2 rad 0.5 s later; then 1 s of steps (the topic is not ordered with the step requests: a wall second
   * for it to arrive first). */
  double target = 0.2;
  trajectory_msgs_msg_dds__JointTrajectoryPoint_ point;
  memset(&point, 0, sizeof(point));
  point.positions._buffer = &target;
  point.positions._length = point.positions._maximum = 1;
  point.time_from_start.sec = 0;
  point.time_from_start.nanosec = 500000000u;
  char *names[1] = {(char *)group_joint};
  trajectory_msgs_msg_dds__JointTrajectory_ trajectory;
  memset(&trajectory, 0, sizeof(trajectory));
  const double start = t + 0.1;
  trajectory.header.stamp.sec = (int32_t)floor(start);
  trajectory.header.stamp.nanosec = (uint32_t)llround((start - floor(start)) * 1e9);
  trajectory.header.frame_id = "";
  trajectory.joint_names._buffer = names;
  trajectory.joint_names._length = trajectory.joint_names._maximum = 1;
  trajectory.points._buffer = &point;
  trajectory.points._length = trajectory.points._maximum = 1;
  dds_write(wr_trajectory, &trajectory);
  dds_sleepfor(DDS_SECS(1));
  memset(&request, 0, sizeof(request));
  request.request_id = 3;
  request.steps = 500;
  dds_write(wr_request, &request);
  double t_followed = -1.0;
  const bool followed = await_reply(rd_reply, 3, &accepted, &t_followed, error, sizeof(error)) && accepted;
  double reached = NAN;
  stamp = -1.0;
  for (int i = 0; i < 20000 && followed && !(stamp >= t_followed - 1e-9); ++i) {
    void *samples[1] = {NULL};
    dds_sample_info_t info;
    while (dds_take(rd_joints, samples, &info, 1, 1) > 0) {
      const sensor_msgs_msg_dds__JointState_ *m = samples[0];
      if (info.valid_data && (uint32_t)group_index < m->position._length) {
        stamp = m->header.stamp.sec + 1e-9 * m->header.stamp.nanosec;
        reached = m->position._buffer[group_index];
      }
      dds_return_loan(rd_joints, samples, 1);
    }
    dds_sleepfor(DDS_MSECS(1));
  }
  check(followed && fabs(reached - target) < 3.0 * M_PI / 180.0,
        "a JointTrajectory on its topic brings the joint to its waypoint [rad]", reached, target);

  /* 5: the newest WrenchStamped, at the last reply's sim time. */
  double wrench_stamp = -1.0, force = NAN;
  bool frame_ok = false, wrench_finite = false;
  for (int i = 0; i < 20000 && followed && !(wrench_stamp >= t_followed - 1e-9); ++i) {
    void *samples[1] = {NULL};
    dds_sample_info_t info;
    while (dds_take(rd_wrench, samples, &info, 1, 1) > 0) {
      const geometry_msgs_msg_dds__WrenchStamped_ *m = samples[0];
      if (info.valid_data) {
        const geometry_msgs_msg_dds__Vector3_ *f = &m->wrench.force, *q = &m->wrench.torque;
        wrench_stamp = m->header.stamp.sec + 1e-9 * m->header.stamp.nanosec;
        frame_ok = m->header.frame_id != NULL && strcmp(m->header.frame_id, wrench_frame) == 0;
        wrench_finite = isfinite(f->x) && isfinite(f->y) && isfinite(f->z) && isfinite(q->x) && isfinite(q->y) &&
                        isfinite(q->z);
        force = sqrt(f->x * f->x + f->y * f->y + f->z * f->z);
      }
      dds_return_loan(rd_wrench, samples, 1);
    }
    dds_sleepfor(DDS_MSECS(1));
  }
  check(fabs(wrench_stamp - t_followed) < 1e-9 && frame_ok, "a WrenchStamped at the reply's sim time, in its frame [s]",
        wrench_stamp, t_followed);
  check(wrench_finite && force > 1.0 && force < 100.0, "the force/torque sensor's force is finite and plausible [N]",
        force, 10.0);

  dds_delete(pp);
  return failures == 0 ? 0 : 1;
}
