/* hadal-ros2-probe: reads hadald's ROS 2 topics with Cyclone DDS (the DDS under rmw_cyclonedds) and,
 * optionally, commands the thrusters, to show that hadald is ROS 2 compatible on the wire.
 *
 * Readers use the ROS 2 DDS names and layouts (ros2_types.idl, final extensibility = XCDR1):
 *   rt/clock                      rosgraph_msgs::msg::dds_::Clock_      RELIABLE, VOLATILE (ROS 2 default)
 *   rt/<vehicle>/odometry         nav_msgs::msg::dds_::Odometry_        RELIABLE and, on a second reader,
 *                                                                       BEST_EFFORT (ROS 2 sensor-data QoS)
 *   rt/<vehicle>/thrusters/state  hadal_msgs::msg::dds_::ThrusterState_ (did our commands arrive?)
 *   rt/hadal/status               hadal_msgs::msg::dds_::SimStatus_     (rejected commands, if any)
 *   rt/<vehicle>/depth            sensor_msgs::msg::dds_::FluidPressure_     } each RELIABLE + KEEP_ALL
 *   rt/<vehicle>/imu              sensor_msgs::msg::dds_::Imu_               } (counts every sample) and,
 *   rt/<vehicle>/magnetometer     sensor_msgs::msg::dds_::MagneticField_     } on a second reader,
 *   rt/<vehicle>/gps              sensor_msgs::msg::dds_::NavSatFix_         } BEST_EFFORT depth 5
 *   rt/<vehicle>/dvl              marine_acoustic_msgs::msg::dds_::Dvl_      } (rclcpp SensorDataQoS)
 *   rt/<vehicle>/altimeter        sensor_msgs::msg::dds_::Range_             }
 * (the sensor names of configs/vehicles/torpedo_auv.yaml) and, with --sonars, the sonars of
 * configs/scenarios/sonar_survey.yaml, each RELIABLE + KEEP_ALL and BEST_EFFORT depth 5 likewise:
 *   rt/<vehicle>/fls                 marine_acoustic_msgs::msg::dds_::ProjectedSonarImage_
 *   rt/<vehicle>/multibeam           marine_acoustic_msgs::msg::dds_::SonarDetections_
 *   rt/<vehicle>/sidescan/port       marine_acoustic_msgs::msg::dds_::RawSonarImage_
 *   rt/<vehicle>/sidescan/starboard  marine_acoustic_msgs::msg::dds_::RawSonarImage_
 * Per sensor topic the JSON has sample counts,
 * the first and last header stamps, the frame_id and a summary (min, max, mean, last) of the decoded
 * values a driver can check against physics; the probe itself judges only clock and odometry.
 * Writer (with --publish-setpoints): rt/<vehicle>/actuators/commands std_msgs::msg::dds_::Float64MultiArray_
 * at --rate-hz (10 Hz), RELIABLE, VOLATILE.
 *
 * Prints one JSON object on stdout; exits 0 when at least one clock and one odometry sample arrived,
 * 1 otherwise, 2 on a usage or DDS set-up error.
 *
 * Discovery stays on loopback unless told otherwise: with ROS_LOCALHOST_ONLY=1 (or
 * ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST), or when nothing else is configured, the probe sets
 * CYCLONEDDS_URI to a loopback-only, unicast-only configuration before creating its participant
 * (hadald does the same with Fast DDS). A CYCLONEDDS_URI set by the user is left alone;
 * --network-discovery keeps Cyclone's defaults (multicast on the default interface).
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "dds/dds.h"
#include "ros2_types.h"

#define MAX_SETPOINTS 16
#define MAX_REMOTE 32
#define TAKE_BATCH 64

static volatile sig_atomic_t g_stop = 0;
static void on_signal(int sig) {
  (void)sig;
  g_stop = 1;
}

static double unix_now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---------------------------------------------------------------------------------------------- */
/* Options                                                                                        */

typedef struct {
  int domain;
  const char *vehicle;
  double seconds;        /* hard wall-clock limit */
  double idle_s;         /* stop once both topics were seen and nothing arrived for this long */
  unsigned long enough;  /* stop once clock and odometry counts both reach this */
  double rate_hz;
  size_t n_setpoints;
  double setpoints[MAX_SETPOINTS];
  bool publish;
  bool network_discovery;
  bool sonars; /* also read the sonar topics */
  const char *trace_file;
} options_t;

static void usage(FILE *out) {
  fprintf(out,
          "usage: hadal-ros2-probe [--domain-id N] [--vehicle NAME] [--seconds T] [--idle S] [--enough K]\n"
          "                        [--publish-setpoints a,b,c] [--rate-hz R] [--network-discovery]\n"
          "                        [--sonars] [--cyclone-trace FILE]\n"
          "  --domain-id N           DDS domain id (default: $ROS_DOMAIN_ID or 0)\n"
          "  --vehicle NAME          vehicle whose topics are read (default: auv)\n"
          "  --seconds T             stop after T wall-clock seconds (default: 10)\n"
          "  --idle S                stop when both topics were seen and nothing arrived for S seconds\n"
          "  --enough K              stop when K clock and K odometry samples arrived\n"
          "  --publish-setpoints L   write setpoints L (comma-separated) to rt/NAME/actuators/commands\n"
          "  --rate-hz R             setpoint rate (default: 10)\n"
          "  --network-discovery     keep Cyclone's default (multicast) discovery unless\n"
          "                          ROS_LOCALHOST_ONLY=1; default is loopback only\n"
          "  --sonars                also read rt/NAME/fls, multibeam, sidescan/port and sidescan/starboard\n"
          "  --cyclone-trace FILE    write Cyclone's trace (finest) to FILE\n");
}

static bool parse_double(const char *s, double *out) {
  char *end = NULL;
  errno = 0;
  double v = strtod(s, &end);
  if (errno != 0 || end == s || *end != '\0' || !isfinite(v)) return false;
  *out = v;
  return true;
}

static bool parse_setpoints(const char *s, options_t *o) {
  o->n_setpoints = 0;
  const char *p = s;
  while (*p != '\0') {
    if (o->n_setpoints == MAX_SETPOINTS) return false;
    char *end = NULL;
    errno = 0;
    double v = strtod(p, &end);
    if (errno != 0 || end == p || !isfinite(v)) return false;
    o->setpoints[o->n_setpoints++] = v;
    if (*end == ',') {
      p = end + 1;
      if (*p == '\0') return false;
    } else if (*end == '\0') {
      p = end;
    } else {
      return false;
    }
  }
  return o->n_setpoints > 0;
}

static int parse_options(int argc, char **argv, options_t *o) {
  memset(o, 0, sizeof(*o));
  o->vehicle = "auv";
  o->seconds = 10.0;
  o->rate_hz = 10.0;
  const char *env_domain = getenv("ROS_DOMAIN_ID");
  if (env_domain != NULL && *env_domain != '\0') o->domain = atoi(env_domain);
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
    double d;
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      usage(stdout);
      exit(0);
    } else if (strcmp(a, "--network-discovery") == 0) {
      o->network_discovery = true;
      continue;
    } else if (strcmp(a, "--sonars") == 0) {
      o->sonars = true;
      continue;
    }
    if (strcmp(a, "--domain") == 0) {  /* the one flag name of Hadal's tools */
      fprintf(stderr, "hadal-ros2-probe: --domain is now --domain-id\n");
      return -1;
    }
    static const char *const with_value[] = {"--domain-id", "--vehicle", "--seconds", "--idle", "--enough",
                                             "--rate-hz", "--publish-setpoints", "--cyclone-trace"};
    bool known = false;
    for (size_t k = 0; k < sizeof(with_value) / sizeof(with_value[0]); ++k) known |= strcmp(a, with_value[k]) == 0;
    if (!known) {
      fprintf(stderr, "hadal-ros2-probe: unknown option %s\n", a);
      return -1;
    }
    if (v == NULL) {
      fprintf(stderr, "hadal-ros2-probe: %s needs a value\n", a);
      return -1;
    }
    ++i;
    if (strcmp(a, "--domain-id") == 0) {
      if (!parse_double(v, &d) || d < 0 || d > 232 || d != floor(d)) {
        fprintf(stderr, "hadal-ros2-probe: --domain-id must be an integer in 0..232 (got %s)\n", v);
        return -1;
      }
      o->domain = (int)d;
    } else if (strcmp(a, "--vehicle") == 0) {
      if (*v == '\0') return -1;
      o->vehicle = v;
    } else if (strcmp(a, "--seconds") == 0) {
      if (!parse_double(v, &o->seconds) || o->seconds <= 0) {
        fprintf(stderr, "hadal-ros2-probe: --seconds must be > 0 (got %s)\n", v);
        return -1;
      }
    } else if (strcmp(a, "--idle") == 0) {
      if (!parse_double(v, &o->idle_s) || o->idle_s <= 0) {
        fprintf(stderr, "hadal-ros2-probe: --idle must be > 0 (got %s)\n", v);
        return -1;
      }
    } else if (strcmp(a, "--enough") == 0) {
      if (!parse_double(v, &d) || d < 1 || d != floor(d)) {
        fprintf(stderr, "hadal-ros2-probe: --enough must be an integer >= 1 (got %s)\n", v);
        return -1;
      }
      o->enough = (unsigned long)d;
    } else if (strcmp(a, "--rate-hz") == 0) {
      if (!parse_double(v, &o->rate_hz) || o->rate_hz <= 0 || o->rate_hz > 1000) {
        fprintf(stderr, "hadal-ros2-probe: --rate-hz must be in (0, 1000] (got %s)\n", v);
        return -1;
      }
    } else if (strcmp(a, "--publish-setpoints") == 0) {
      if (!parse_setpoints(v, o)) {
        fprintf(stderr,
                "hadal-ros2-probe: --publish-setpoints wants 1..%d comma-separated numbers (got %s)\n",
                MAX_SETPOINTS, v);
        return -1;
      }
      o->publish = true;
    } else if (strcmp(a, "--cyclone-trace") == 0) {
      o->trace_file = v;
    } else {
      fprintf(stderr, "hadal-ros2-probe: unknown option %s\n", a);
      return -1;
    }
  }
  return 0;
}

/* ---------------------------------------------------------------------------------------------- */
/* Cyclone configuration: loopback only                                                           */

static bool env_is(const char *name, const char *value) {
  const char *v = getenv(name);
  return v != NULL && strcmp(v, value) == 0;
}

/* Returns a short description of where the configuration came from, for the JSON report. */
static const char *configure_discovery(const options_t *o, char *xml, size_t xml_size) {
  const char *user_uri = getenv("CYCLONEDDS_URI");
  if (user_uri != NULL && *user_uri != '\0') return "user CYCLONEDDS_URI";
  const bool localhost_only =
      env_is("ROS_LOCALHOST_ONLY", "1") || env_is("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST");
  if (!localhost_only && o->network_discovery) return "cyclone defaults";
  /* Loopback interface, no multicast, SPDP by unicast to 127.0.0.1 for participant indices 0..31 (the
   * ports hadald's Fast DDS participant also announces itself on under ROS_LOCALHOST_ONLY=1). */
  char tracing[1024] = "";
  if (o->trace_file != NULL) {
    snprintf(tracing, sizeof(tracing),
             "<Tracing><Verbosity>finest</Verbosity><OutputFile>%s</OutputFile></Tracing>", o->trace_file);
  }
  snprintf(xml, xml_size,
           "<CycloneDDS><Domain id=\"any\">"
           "<General><Interfaces><NetworkInterface address=\"127.0.0.1\"/></Interfaces>"
           "<AllowMulticast>false</AllowMulticast></General>"
           "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
           "<MaxAutoParticipantIndex>31</MaxAutoParticipantIndex>"
           "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>"
           "%s</Domain></CycloneDDS>",
           tracing);
  setenv("CYCLONEDDS_URI", xml, 1);
  return localhost_only ? "probe loopback (ROS_LOCALHOST_ONLY)" : "probe loopback (default)";
}

/* ---------------------------------------------------------------------------------------------- */
/* Statistics                                                                                     */

typedef struct {
  int32_t sec;
  uint32_t nanosec;
} stamp_t;

static double stamp_s(stamp_t t) { return (double)t.sec + 1e-9 * (double)t.nanosec; }

typedef struct {
  unsigned long count;
  double first_match_s; /* probe-relative wall time of the first match; < 0 if never */
  double first_sample_s;
  uint32_t matched_now;
} endpoint_stats_t;

/* min / max / mean / last over the finite values seen; `non_finite` counts the others. */
typedef struct {
  unsigned long n, non_finite;
  double min, max, sum, last;
} summary_t;

static void summary_add(summary_t *m, double v) {
  if (!isfinite(v)) {
    ++m->non_finite;
    return;
  }
  if (m->n == 0 || v < m->min) m->min = v;
  if (m->n == 0 || v > m->max) m->max = v;
  m->sum += v;
  m->last = v;
  ++m->n;
}

/* The default AUV's sensors (configs/vehicles/torpedo_auv.yaml), read on rt/<vehicle>/<name>, and the sonars of
 * configs/scenarios/sonar_survey.yaml (with --sonars). */
enum sensor_kind {
  S_DEPTH,
  S_IMU,
  S_MAGNETOMETER,
  S_GPS,
  S_DVL,
  S_ALTIMETER,
  S_FLS,
  S_MULTIBEAM,
  S_SIDESCAN_PORT,
  S_SIDESCAN_STARBOARD,
  S_COUNT
};

typedef struct {
  const char *name;
  const dds_topic_descriptor_t *desc;
  bool sonar; /* read only with --sonars */
} sensor_info_t;

static const sensor_info_t k_sensors[S_COUNT] = {
    [S_DEPTH] = {"depth", &sensor_msgs_msg_dds__FluidPressure__desc, false},
    [S_IMU] = {"imu", &sensor_msgs_msg_dds__Imu__desc, false},
    [S_MAGNETOMETER] = {"magnetometer", &sensor_msgs_msg_dds__MagneticField__desc, false},
    [S_GPS] = {"gps", &sensor_msgs_msg_dds__NavSatFix__desc, false},
    [S_DVL] = {"dvl", &marine_acoustic_msgs_msg_dds__Dvl__desc, false},
    [S_ALTIMETER] = {"altimeter", &sensor_msgs_msg_dds__Range__desc, false},
    [S_FLS] = {"fls", &marine_acoustic_msgs_msg_dds__ProjectedSonarImage__desc, true},
    [S_MULTIBEAM] = {"multibeam", &marine_acoustic_msgs_msg_dds__SonarDetections__desc, true},
    [S_SIDESCAN_PORT] = {"sidescan/port", &marine_acoustic_msgs_msg_dds__RawSonarImage__desc, true},
    [S_SIDESCAN_STARBOARD] = {"sidescan/starboard", &marine_acoustic_msgs_msg_dds__RawSonarImage__desc, true},
};

static bool sensor_enabled(const options_t *o, int k) { return !k_sensors[k].sonar || o->sonars; }

/* Everything but the endpoint counts comes from the reliable reader, which sees every sample. */
typedef struct {
  endpoint_stats_t reliable;
  endpoint_stats_t best_effort;
  unsigned long seen;
  stamp_t first_stamp, last_stamp;
  unsigned long stamp_not_increasing; /* a stamp <= the one before (or nanosec >= 1e9) */
  char frame_id[128];
  unsigned long frame_id_changes;
  unsigned long non_finite; /* samples with a number that must be finite but is not */
  /* depth: FluidPressure */
  summary_t pressure; /* [Pa] */
  double variance;    /* [Pa^2], last */
  /* imu: Imu */
  summary_t specific_force_norm; /* |linear_acceleration| [m/s^2] */
  summary_t angular_rate_norm;   /* |angular_velocity| [rad/s] */
  double linear_acceleration[3], angular_velocity[3];
  unsigned long orientation_reported; /* samples with orientation_covariance[0] != -1 */
  double angular_velocity_variance[3], linear_acceleration_variance[3]; /* covariance diagonals, last */
  /* magnetometer: MagneticField */
  summary_t field_norm_ut; /* |magnetic_field| [uT] */
  double magnetic_field[3]; /* [T], last */
  /* gps: NavSatFix */
  summary_t status; /* NavSatStatus.status */
  unsigned long samples_with_position; /* latitude, longitude and altitude all finite */
  unsigned service, covariance_type;
  /* dvl: Dvl */
  unsigned long mode_bottom, mode_water, mode_other;
  summary_t good_beams, altitude, speed; /* speed = |velocity| [m/s] */
  double velocity[3], dvl_range[4];
  unsigned dvl_type;
  double sound_speed;
  bool beam_ranges_valid, beam_velocities_valid;
  /* altimeter: Range */
  summary_t range;
  unsigned long range_outside_limits; /* finite range outside [min_range, max_range] */
  double min_range, max_range, field_of_view;
  unsigned radiation_type;
  /* sonars: ping_info, and the image (fls, sidescan) or the detections (multibeam), last sample */
  double frequency, sonar_sound_speed;
  unsigned long beams, bins, image_bytes, nonzero_samples;
  unsigned dtype;
  unsigned long mismatched_lengths; /* samples whose array lengths disagree with each other */
  summary_t detected_beams;         /* multibeam: beams flagged DETECT_OK */
  summary_t detected_range;         /* multibeam: c t / 2 of the good beams [m] */
  double sample_rate, rx_angle;     /* sidescan */
  unsigned long sample0;
} sensor_stats_t;

typedef struct {
  endpoint_stats_t clock;
  endpoint_stats_t odom_reliable;
  endpoint_stats_t odom_best_effort;
  endpoint_stats_t thruster_state;
  endpoint_stats_t status;
  endpoint_stats_t setpoint_writer; /* count = samples written */

  unsigned long clock_seen; /* counted per sample (endpoint counts are updated per batch) */
  stamp_t clock_first, clock_last;
  bool clock_non_decreasing;
  unsigned long clock_decreases;

  /* last odometry sample (reliable reader) */
  stamp_t odom_stamp;
  char odom_frame_id[128];
  char odom_child_frame_id[128];
  double pos[3], quat[4], lin[3], ang[3];
  /* sanity over every odometry sample, both readers */
  unsigned long odom_insane;
  char odom_insane_reason[256];
  double quat_norm_max_error;

  /* thruster state */
  unsigned long thruster_client_samples; /* command_source == SOURCE_CLIENT (2) */
  bool setpoints_echoed;                 /* a client-commanded sample carried exactly our setpoints */
  uint8_t last_command_source;
  size_t last_thruster_n;
  double last_thruster_setpoints[MAX_SETPOINTS];

  /* status */
  unsigned long long rejected_commands;
  char last_error[256];
  size_t n_faults;
  double vehicle_faults[MAX_SETPOINTS]; /* FAULT_* bits per vehicle (as numbers for the JSON writer) */
  double last_status_sim_time;
  uint8_t mode;

  double last_sample_s; /* probe-relative time of the last clock/odometry/sensor sample */

  sensor_stats_t sensors[S_COUNT];

  size_t n_remote;
  struct {
    char topic[128];
    char type[160];
  } remote[MAX_REMOTE];
} stats_t;

static void endpoint_init(endpoint_stats_t *e) {
  memset(e, 0, sizeof(*e));
  e->first_match_s = -1.0;
  e->first_sample_s = -1.0;
}

static void copy_str(char *dst, size_t size, const char *src) {
  snprintf(dst, size, "%s", src != NULL ? src : "");
}

static void note_insane(stats_t *s, const char *reason) {
  if (s->odom_insane++ == 0) copy_str(s->odom_insane_reason, sizeof(s->odom_insane_reason), reason);
}

static bool all_finite(const double *v, size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (!isfinite(v[i])) return false;
  return true;
}

static void on_odometry(stats_t *s, const nav_msgs_msg_dds__Odometry_ *m, bool keep_as_last) {
  const geometry_msgs_msg_dds__Pose_ *pose = &m->pose.pose;
  const geometry_msgs_msg_dds__Twist_ *twist = &m->twist.twist;
  double pos[3] = {pose->position.x, pose->position.y, pose->position.z};
  double quat[4] = {pose->orientation.x, pose->orientation.y, pose->orientation.z, pose->orientation.w};
  double lin[3] = {twist->linear.x, twist->linear.y, twist->linear.z};
  double ang[3] = {twist->angular.x, twist->angular.y, twist->angular.z};
  if (!all_finite(pos, 3) || !all_finite(quat, 4) || !all_finite(lin, 3) || !all_finite(ang, 3) ||
      !all_finite(m->pose.covariance, 36) || !all_finite(m->twist.covariance, 36)) {
    note_insane(s, "non-finite number in odometry");
  }
  const double norm = sqrt(quat[0] * quat[0] + quat[1] * quat[1] + quat[2] * quat[2] + quat[3] * quat[3]);
  const double err = fabs(norm - 1.0);
  if (!(err <= 1e-6)) {
    char reason[128];
    snprintf(reason, sizeof(reason), "orientation quaternion norm %.17g", norm);
    note_insane(s, reason);
  }
  if (isfinite(err) && err > s->quat_norm_max_error) s->quat_norm_max_error = err;
  if (m->header.frame_id == NULL || m->header.frame_id[0] == '\0') note_insane(s, "empty header.frame_id");
  if (m->child_frame_id == NULL || m->child_frame_id[0] == '\0') note_insane(s, "empty child_frame_id");
  if (m->header.stamp.nanosec >= 1000000000u) note_insane(s, "header.stamp.nanosec >= 1e9");
  if (!keep_as_last) return;
  s->odom_stamp.sec = m->header.stamp.sec;
  s->odom_stamp.nanosec = m->header.stamp.nanosec;
  copy_str(s->odom_frame_id, sizeof(s->odom_frame_id), m->header.frame_id);
  copy_str(s->odom_child_frame_id, sizeof(s->odom_child_frame_id), m->child_frame_id);
  memcpy(s->pos, pos, sizeof(pos));
  memcpy(s->quat, quat, sizeof(quat));
  memcpy(s->lin, lin, sizeof(lin));
  memcpy(s->ang, ang, sizeof(ang));
}

static void on_clock(stats_t *s, const rosgraph_msgs_msg_dds__Clock_ *m) {
  stamp_t t = {m->clock.sec, m->clock.nanosec};
  if (s->clock_seen++ == 0) {
    s->clock_first = t;
  } else if (t.sec < s->clock_last.sec || (t.sec == s->clock_last.sec && t.nanosec < s->clock_last.nanosec)) {
    s->clock_non_decreasing = false;
    ++s->clock_decreases;
  }
  if (t.nanosec >= 1000000000u) s->clock_non_decreasing = false;
  s->clock_last = t;
}

static void on_thruster_state(stats_t *s, const options_t *o, const hadal_msgs_msg_dds__ThrusterState_ *m) {
  s->last_command_source = m->command_source;
  size_t n = m->setpoint._length;
  s->last_thruster_n = n;
  for (size_t i = 0; i < n && i < MAX_SETPOINTS; ++i) s->last_thruster_setpoints[i] = m->setpoint._buffer[i];
  if (m->command_source != 2) return;
  ++s->thruster_client_samples;
  if (!o->publish || n != o->n_setpoints) return;
  for (size_t i = 0; i < n; ++i)
    if (m->setpoint._buffer[i] != o->setpoints[i]) return;
  s->setpoints_echoed = true;
}

static void on_status(stats_t *s, const hadal_msgs_msg_dds__SimStatus_ *m) {
  s->rejected_commands = (unsigned long long)m->rejected_commands;
  copy_str(s->last_error, sizeof(s->last_error), m->last_error);
  s->last_status_sim_time = m->sim_time;
  s->mode = m->mode;
  s->n_faults = m->vehicle_faults._length < MAX_SETPOINTS ? m->vehicle_faults._length : MAX_SETPOINTS;
  for (size_t i = 0; i < s->n_faults; ++i) s->vehicle_faults[i] = (double)m->vehicle_faults._buffer[i];
}

static double norm3(double x, double y, double z) { return sqrt(x * x + y * y + z * z); }

/* Header bookkeeping common to all sensor messages. */
static void on_sensor_header(sensor_stats_t *m, const std_msgs_msg_dds__Header_ *h) {
  stamp_t t = {h->stamp.sec, h->stamp.nanosec};
  if (t.nanosec >= 1000000000u) ++m->stamp_not_increasing;
  if (m->seen == 0) {
    m->first_stamp = t;
    copy_str(m->frame_id, sizeof(m->frame_id), h->frame_id);
  } else {
    if (t.sec < m->last_stamp.sec || (t.sec == m->last_stamp.sec && t.nanosec <= m->last_stamp.nanosec))
      ++m->stamp_not_increasing;
    if (strcmp(m->frame_id, h->frame_id != NULL ? h->frame_id : "") != 0) ++m->frame_id_changes;
  }
  m->last_stamp = t;
  ++m->seen;
}

static void on_fluid_pressure(sensor_stats_t *m, const sensor_msgs_msg_dds__FluidPressure_ *x) {
  on_sensor_header(m, &x->header);
  if (!isfinite(x->fluid_pressure) || !isfinite(x->variance)) ++m->non_finite;
  summary_add(&m->pressure, x->fluid_pressure);
  m->variance = x->variance;
}

static void on_imu(sensor_stats_t *m, const sensor_msgs_msg_dds__Imu_ *x) {
  on_sensor_header(m, &x->header);
  const double f[3] = {x->linear_acceleration.x, x->linear_acceleration.y, x->linear_acceleration.z};
  const double w[3] = {x->angular_velocity.x, x->angular_velocity.y, x->angular_velocity.z};
  if (!all_finite(f, 3) || !all_finite(w, 3) || !all_finite(x->angular_velocity_covariance, 9) ||
      !all_finite(x->linear_acceleration_covariance, 9))
    ++m->non_finite;
  summary_add(&m->specific_force_norm, norm3(f[0], f[1], f[2]));
  summary_add(&m->angular_rate_norm, norm3(w[0], w[1], w[2]));
  memcpy(m->linear_acceleration, f, sizeof(f));
  memcpy(m->angular_velocity, w, sizeof(w));
  if (x->orientation_covariance[0] != -1.0) ++m->orientation_reported;
  for (int a = 0; a < 3; ++a) {
    m->angular_velocity_variance[a] = x->angular_velocity_covariance[4 * a];
    m->linear_acceleration_variance[a] = x->linear_acceleration_covariance[4 * a];
  }
}

static void on_magnetic_field(sensor_stats_t *m, const sensor_msgs_msg_dds__MagneticField_ *x) {
  on_sensor_header(m, &x->header);
  const double b[3] = {x->magnetic_field.x, x->magnetic_field.y, x->magnetic_field.z};
  if (!all_finite(b, 3) || !all_finite(x->magnetic_field_covariance, 9)) ++m->non_finite;
  summary_add(&m->field_norm_ut, 1e6 * norm3(b[0], b[1], b[2]));
  memcpy(m->magnetic_field, b, sizeof(b));
}

static void on_nav_sat_fix(sensor_stats_t *m, const sensor_msgs_msg_dds__NavSatFix_ *x) {
  on_sensor_header(m, &x->header);
  /* Without a fix latitude, longitude and altitude may be NaN; the covariance is always known. */
  if (!all_finite(x->position_covariance, 9)) ++m->non_finite;
  summary_add(&m->status, (double)x->status.status);
  if (isfinite(x->latitude) && isfinite(x->longitude) && isfinite(x->altitude)) ++m->samples_with_position;
  m->service = x->status.service;
  m->covariance_type = x->position_covariance_type;
}

static void on_dvl(sensor_stats_t *m, const marine_acoustic_msgs_msg_dds__Dvl_ *x) {
  on_sensor_header(m, &x->header);
  const double v[3] = {x->velocity.x, x->velocity.y, x->velocity.z};
  const bool locked = x->velocity_mode == marine_acoustic_msgs_msg_Dvl_Constants_DVL_MODE_BOTTOM ||
                      x->velocity_mode == marine_acoustic_msgs_msg_Dvl_Constants_DVL_MODE_WATER;
  if (x->velocity_mode == marine_acoustic_msgs_msg_Dvl_Constants_DVL_MODE_BOTTOM) ++m->mode_bottom;
  else if (x->velocity_mode == marine_acoustic_msgs_msg_Dvl_Constants_DVL_MODE_WATER) ++m->mode_water;
  else ++m->mode_other;
  /* A velocity (and, in bottom track, an altitude) is a number whenever the DVL has a solution. */
  if (locked && !all_finite(v, 3)) ++m->non_finite;
  if (x->velocity_mode == marine_acoustic_msgs_msg_Dvl_Constants_DVL_MODE_BOTTOM && !isfinite(x->altitude))
    ++m->non_finite;
  summary_add(&m->good_beams, (double)x->num_good_beams);
  summary_add(&m->altitude, x->altitude);
  summary_add(&m->speed, norm3(v[0], v[1], v[2]));
  memcpy(m->velocity, v, sizeof(v));
  memcpy(m->dvl_range, x->range, sizeof(m->dvl_range));
  m->dvl_type = x->dvl_type;
  m->sound_speed = x->sound_speed;
  m->beam_ranges_valid = x->beam_ranges_valid;
  m->beam_velocities_valid = x->beam_velocities_valid;
}

static void on_range(sensor_stats_t *m, const sensor_msgs_msg_dds__Range_ *x) {
  on_sensor_header(m, &x->header);
  /* REP 117: a range may be -Inf / +Inf (closer than min_range / nothing within max_range). */
  if (!isfinite(x->min_range) || !isfinite(x->max_range) || !isfinite(x->field_of_view) || isnan(x->range))
    ++m->non_finite;
  summary_add(&m->range, x->range);
  if (isfinite(x->range) && (x->range < x->min_range || x->range > x->max_range)) ++m->range_outside_limits;
  m->min_range = x->min_range;
  m->max_range = x->max_range;
  m->field_of_view = x->field_of_view;
  m->radiation_type = x->radiation_type;
}

static void on_ping_info(sensor_stats_t *m, const marine_acoustic_msgs_msg_dds__PingInfo_ *p) {
  m->frequency = p->frequency;
  m->sonar_sound_speed = p->sound_speed;
  if (!isfinite(p->frequency) || !isfinite(p->sound_speed)) ++m->non_finite;
}

/* Samples, not bytes: a float32 sample (dtype 8) is four bytes, little-endian. */
static void on_sonar_image_data(sensor_stats_t *m, const marine_acoustic_msgs_msg_dds__SonarImageData_ *d) {
  m->dtype = d->dtype;
  m->image_bytes = d->data._length;
  m->nonzero_samples = 0;
  const uint32_t size = d->dtype == 8 ? 4 : 1;
  for (uint32_t i = 0; i + size <= d->data._length; i += size) {
    bool nonzero = false;
    for (uint32_t k = 0; k < size; ++k) nonzero |= d->data._buffer[i + k] != 0;
    m->nonzero_samples += nonzero;
  }
}

static void on_projected_sonar_image(sensor_stats_t *m, const marine_acoustic_msgs_msg_dds__ProjectedSonarImage_ *x) {
  on_sensor_header(m, &x->header);
  on_ping_info(m, &x->ping_info);
  on_sonar_image_data(m, &x->image);
  m->beams = x->beam_directions._length;
  m->bins = x->ranges._length;
  const unsigned long size = x->image.dtype == 8 ? 4 : 1;
  if (x->image.beam_count != m->beams || m->image_bytes != m->beams * m->bins * size ||
      x->ping_info.rx_beamwidths._length != m->beams)
    ++m->mismatched_lengths;
}

static void on_sonar_detections(sensor_stats_t *m, const marine_acoustic_msgs_msg_dds__SonarDetections_ *x) {
  on_sensor_header(m, &x->header);
  on_ping_info(m, &x->ping_info);
  const uint32_t n = x->flags._length;
  m->beams = n;
  if (x->two_way_travel_times._length != n || x->intensities._length != n || x->rx_angles._length != n ||
      x->tx_angles._length != n || x->tx_delays._length != n)
    ++m->mismatched_lengths;
  unsigned long good = 0;
  for (uint32_t i = 0; i < n && i < x->two_way_travel_times._length; ++i) {
    if (x->flags._buffer[i].flag != 0) continue;
    ++good;
    summary_add(&m->detected_range, 0.5 * x->ping_info.sound_speed * x->two_way_travel_times._buffer[i]);
  }
  summary_add(&m->detected_beams, (double)good);
}

static void on_raw_sonar_image(sensor_stats_t *m, const marine_acoustic_msgs_msg_dds__RawSonarImage_ *x) {
  on_sensor_header(m, &x->header);
  on_ping_info(m, &x->ping_info);
  on_sonar_image_data(m, &x->image);
  m->beams = x->image.beam_count;
  m->bins = x->samples_per_beam;
  m->sample_rate = x->sample_rate;
  m->sample0 = x->sample0;
  m->rx_angle = x->rx_angles._length > 0 ? x->rx_angles._buffer[0] : NAN;
  const unsigned long size = x->image.dtype == 8 ? 4 : 1;
  if (m->image_bytes != m->beams * m->bins * size) ++m->mismatched_lengths;
}

static void on_sensor_sample(enum sensor_kind k, sensor_stats_t *m, const void *sample) {
  switch (k) {
    case S_DEPTH: on_fluid_pressure(m, sample); break;
    case S_IMU: on_imu(m, sample); break;
    case S_MAGNETOMETER: on_magnetic_field(m, sample); break;
    case S_GPS: on_nav_sat_fix(m, sample); break;
    case S_DVL: on_dvl(m, sample); break;
    case S_ALTIMETER: on_range(m, sample); break;
    case S_FLS: on_projected_sonar_image(m, sample); break;
    case S_MULTIBEAM: on_sonar_detections(m, sample); break;
    case S_SIDESCAN_PORT:
    case S_SIDESCAN_STARBOARD: on_raw_sonar_image(m, sample); break;
    default: break;
  }
}

/* ---------------------------------------------------------------------------------------------- */
/* JSON output                                                                                    */

static void json_string(FILE *f, const char *s) {
  fputc('"', f);
  for (const unsigned char *p = (const unsigned char *)(s != NULL ? s : ""); *p; ++p) {
    switch (*p) {
      case '"': fputs("\\\"", f); break;
      case '\\': fputs("\\\\", f); break;
      case '\n': fputs("\\n", f); break;
      case '\r': fputs("\\r", f); break;
      case '\t': fputs("\\t", f); break;
      default:
        if (*p < 0x20) fprintf(f, "\\u%04x", *p);
        else fputc(*p, f);
    }
  }
  fputc('"', f);
}

static void json_number(FILE *f, double v) {
  if (isfinite(v)) fprintf(f, "%.17g", v);
  else fputs("null", f);
}

static void json_vec(FILE *f, const double *v, size_t n) {
  fputc('[', f);
  for (size_t i = 0; i < n; ++i) {
    if (i) fputs(", ", f);
    json_number(f, v[i]);
  }
  fputc(']', f);
}

static void json_stamp(FILE *f, stamp_t t) {
  fprintf(f, "{\"sec\": %d, \"nanosec\": %u, \"s\": ", (int)t.sec, (unsigned)t.nanosec);
  json_number(f, stamp_s(t));
  fputc('}', f);
}

static void json_endpoint(FILE *f, const char *name, const endpoint_stats_t *e, const char *count_name) {
  fprintf(f, "\"%s\": {\"%s\": %lu, \"matched_at_end\": %u, \"first_match_s\": ", name, count_name, e->count,
          (unsigned)e->matched_now);
  json_number(f, e->first_match_s >= 0 ? e->first_match_s : NAN);
  fputs(", \"first_sample_s\": ", f);
  json_number(f, e->first_sample_s >= 0 ? e->first_sample_s : NAN);
  fputc('}', f);
}

static void json_summary(FILE *f, const char *name, const summary_t *m) {
  fprintf(f, ", \"%s\": {\"n\": %lu, \"non_finite\": %lu, \"min\": ", name, m->n, m->non_finite);
  json_number(f, m->n > 0 ? m->min : NAN);
  fputs(", \"max\": ", f);
  json_number(f, m->n > 0 ? m->max : NAN);
  fputs(", \"mean\": ", f);
  json_number(f, m->n > 0 ? m->sum / (double)m->n : NAN);
  fputs(", \"last\": ", f);
  json_number(f, m->n > 0 ? m->last : NAN);
  fputc('}', f);
}

static void json_named_number(FILE *f, const char *name, double v) {
  fprintf(f, ", \"%s\": ", name);
  json_number(f, v);
}

static void json_named_vec(FILE *f, const char *name, const double *v, size_t n) {
  fprintf(f, ", \"%s\": ", name);
  json_vec(f, v, n);
}

static void json_sensor(FILE *f, enum sensor_kind k, const char *topic, const sensor_stats_t *m) {
  fprintf(f, "\"%s\": {\"topic\": ", k_sensors[k].name);
  json_string(f, topic);
  fputs(", \"type\": ", f);
  json_string(f, k_sensors[k].desc->m_typename);
  fprintf(f, ", \"count\": %lu, \"matched_at_end\": %u", m->reliable.count, (unsigned)m->reliable.matched_now);
  json_named_number(f, "first_match_s", m->reliable.first_match_s >= 0 ? m->reliable.first_match_s : NAN);
  json_named_number(f, "first_sample_s", m->reliable.first_sample_s >= 0 ? m->reliable.first_sample_s : NAN);
  fprintf(f, ", \"best_effort_count\": %lu, \"best_effort_matched_at_end\": %u", m->best_effort.count,
          (unsigned)m->best_effort.matched_now);
  if (m->seen == 0) {
    fputs("}", f);
    return;
  }
  fputs(", \"first_stamp\": ", f);
  json_stamp(f, m->first_stamp);
  fputs(", \"last_stamp\": ", f);
  json_stamp(f, m->last_stamp);
  fprintf(f, ", \"stamps_not_increasing\": %lu, \"frame_id\": ", m->stamp_not_increasing);
  json_string(f, m->frame_id);
  fprintf(f, ", \"frame_id_changes\": %lu, \"non_finite_samples\": %lu", m->frame_id_changes, m->non_finite);
  switch (k) {
    case S_DEPTH:
      json_summary(f, "fluid_pressure", &m->pressure);
      json_named_number(f, "variance", m->variance);
      break;
    case S_IMU:
      json_summary(f, "specific_force_norm", &m->specific_force_norm);
      json_summary(f, "angular_rate_norm", &m->angular_rate_norm);
      json_named_vec(f, "linear_acceleration", m->linear_acceleration, 3);
      json_named_vec(f, "angular_velocity", m->angular_velocity, 3);
      json_named_vec(f, "linear_acceleration_variance", m->linear_acceleration_variance, 3);
      json_named_vec(f, "angular_velocity_variance", m->angular_velocity_variance, 3);
      fprintf(f, ", \"orientation_reported\": %lu", m->orientation_reported);
      break;
    case S_MAGNETOMETER:
      json_summary(f, "field_norm_ut", &m->field_norm_ut);
      json_named_vec(f, "magnetic_field", m->magnetic_field, 3);
      break;
    case S_GPS:
      json_summary(f, "status", &m->status);
      fprintf(f, ", \"samples_with_position\": %lu, \"service\": %u, \"position_covariance_type\": %u",
              m->samples_with_position, m->service, m->covariance_type);
      break;
    case S_DVL:
      fprintf(f, ", \"mode_bottom\": %lu, \"mode_water\": %lu, \"mode_other\": %lu", m->mode_bottom,
              m->mode_water, m->mode_other);
      json_summary(f, "num_good_beams", &m->good_beams);
      json_summary(f, "altitude", &m->altitude);
      json_summary(f, "speed", &m->speed);
      json_named_vec(f, "velocity", m->velocity, 3);
      json_named_vec(f, "range", m->dvl_range, 4);
      fprintf(f, ", \"dvl_type\": %u, \"beam_ranges_valid\": %s, \"beam_velocities_valid\": %s", m->dvl_type,
              m->beam_ranges_valid ? "true" : "false", m->beam_velocities_valid ? "true" : "false");
      json_named_number(f, "sound_speed", m->sound_speed);
      break;
    case S_ALTIMETER:
      json_summary(f, "range", &m->range);
      fprintf(f, ", \"range_outside_limits\": %lu, \"radiation_type\": %u", m->range_outside_limits,
              m->radiation_type);
      json_named_number(f, "min_range", m->min_range);
      json_named_number(f, "max_range", m->max_range);
      json_named_number(f, "field_of_view", m->field_of_view);
      break;
    case S_FLS:
    case S_SIDESCAN_PORT:
    case S_SIDESCAN_STARBOARD:
      fprintf(f, ", \"beams\": %lu, \"bins\": %lu, \"dtype\": %u, \"image_bytes\": %lu, \"nonzero_samples\": %lu, "
              "\"mismatched_lengths\": %lu", m->beams, m->bins, m->dtype, m->image_bytes, m->nonzero_samples,
              m->mismatched_lengths);
      json_named_number(f, "frequency", m->frequency);
      json_named_number(f, "sound_speed", m->sonar_sound_speed);
      if (k != S_FLS) {
        json_named_number(f, "sample_rate", m->sample_rate);
        json_named_number(f, "rx_angle", m->rx_angle);
        fprintf(f, ", \"sample0\": %lu", m->sample0);
      }
      break;
    case S_MULTIBEAM:
      fprintf(f, ", \"beams\": %lu, \"mismatched_lengths\": %lu", m->beams, m->mismatched_lengths);
      json_named_number(f, "frequency", m->frequency);
      json_named_number(f, "sound_speed", m->sonar_sound_speed);
      json_summary(f, "detected_beams", &m->detected_beams);
      json_summary(f, "detected_range", &m->detected_range);
      break;
    default: break;
  }
  fputc('}', f);
}

static void print_report(const options_t *o, const stats_t *s, char sensor_topics[][256], const char *config_source,
                         double start_unix, double elapsed,
                         const char *stop_reason, bool sane, bool ok) {
  FILE *f = stdout;
  fputs("{", f);
  fprintf(f, "\"probe\": \"hadal-ros2-probe\", \"dds\": \"cyclonedds\", \"domain\": %d, \"vehicle\": ", o->domain);
  json_string(f, o->vehicle);
  fputs(", \"discovery_config\": ", f);
  json_string(f, config_source);
  fputs(", \"start_unix_s\": ", f);
  fprintf(f, "%.6f", start_unix);
  fputs(", \"elapsed_s\": ", f);
  json_number(f, elapsed);
  fputs(", \"stop_reason\": ", f);
  json_string(f, stop_reason);

  fprintf(f, ", \"clock\": {\"count\": %lu, \"matched_at_end\": %u, \"first_match_s\": ", s->clock.count,
          (unsigned)s->clock.matched_now);
  json_number(f, s->clock.first_match_s >= 0 ? s->clock.first_match_s : NAN);
  fputs(", \"first_sample_s\": ", f);
  json_number(f, s->clock.first_sample_s >= 0 ? s->clock.first_sample_s : NAN);
  if (s->clock.count > 0) {
    fputs(", \"first\": ", f);
    json_stamp(f, s->clock_first);
    fputs(", \"last\": ", f);
    json_stamp(f, s->clock_last);
  } else {
    fputs(", \"first\": null, \"last\": null", f);
  }
  fprintf(f, ", \"non_decreasing\": %s, \"decreases\": %lu}", s->clock_non_decreasing ? "true" : "false",
          s->clock_decreases);

  fprintf(f, ", \"odometry\": {\"count\": %lu, \"matched_at_end\": %u, \"first_match_s\": ", s->odom_reliable.count,
          (unsigned)s->odom_reliable.matched_now);
  json_number(f, s->odom_reliable.first_match_s >= 0 ? s->odom_reliable.first_match_s : NAN);
  fputs(", \"first_sample_s\": ", f);
  json_number(f, s->odom_reliable.first_sample_s >= 0 ? s->odom_reliable.first_sample_s : NAN);
  fprintf(f, ", \"best_effort_count\": %lu, \"best_effort_matched_at_end\": %u", s->odom_best_effort.count,
          (unsigned)s->odom_best_effort.matched_now);
  if (s->odom_reliable.count > 0) {
    const double *q = s->quat;
    fputs(",   \"last\": {\"stamp\": ", f);
    json_stamp(f, s->odom_stamp);
    fputs(", \"frame_id\": ", f);
    json_string(f, s->odom_frame_id);
    fputs(", \"child_frame_id\": ", f);
    json_string(f, s->odom_child_frame_id);
    fputs(", \"position\": ", f);
    json_vec(f, s->pos, 3);
    fputs(", \"orientation_xyzw\": ", f);
    json_vec(f, s->quat, 4);
    fputs(", \"orientation_norm\": ", f);
    json_number(f, sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]));
    fputs(", \"linear_velocity\": ", f);
    json_vec(f, s->lin, 3);
    fputs(", \"angular_velocity\": ", f);
    json_vec(f, s->ang, 3);
    fputc('}', f);
  } else {
    fputs(", \"last\": null", f);
  }
  fprintf(f, ", \"insane_samples\": %lu, \"insane_reason\": ", s->odom_insane);
  json_string(f, s->odom_insane_reason);
  fputs(", \"quaternion_norm_max_error\": ", f);
  json_number(f, s->quat_norm_max_error);
  fputc('}', f);

  fputs(", ", f);
  json_endpoint(f, "setpoints", &s->setpoint_writer, "written");
  fputs(", \"setpoints_sent\": ", f);
  if (o->publish) json_vec(f, o->setpoints, o->n_setpoints);
  else fputs("null", f);

  fprintf(f, ", \"thruster_state\": {\"count\": %lu, \"client_commanded\": %lu, \"setpoints_echoed\": %s, "
             "\"last_command_source\": %u, \"last_setpoints\": ",
          s->thruster_state.count, s->thruster_client_samples, s->setpoints_echoed ? "true" : "false",
          (unsigned)s->last_command_source);
  json_vec(f, s->last_thruster_setpoints, s->last_thruster_n < MAX_SETPOINTS ? s->last_thruster_n : MAX_SETPOINTS);
  fputc('}', f);

  fprintf(f, ", \"status\": {\"count\": %lu, \"mode\": %u, \"sim_time\": ", s->status.count, (unsigned)s->mode);
  json_number(f, s->last_status_sim_time);
  fprintf(f, ", \"rejected_commands\": %llu, \"last_error\": ", s->rejected_commands);
  json_string(f, s->last_error);
  fputs(", \"vehicle_faults\": ", f);
  json_vec(f, s->vehicle_faults, s->n_faults);
  fputc('}', f);

  fputs(", \"sensors\": {", f);
  for (int k = 0; k < S_COUNT; ++k) {
    if (!sensor_enabled(o, k)) continue;
    fputs(k ? ", " : "", f);
    json_sensor(f, (enum sensor_kind)k, sensor_topics[k], &s->sensors[k]);
  }
  fputc('}', f);

  fputs(", \"remote_publications\": [", f);
  for (size_t i = 0; i < s->n_remote; ++i) {
    fputs(i ? ", " : "", f);
    fputs("{\"topic\": ", f);
    json_string(f, s->remote[i].topic);
    fputs(", \"type\": ", f);
    json_string(f, s->remote[i].type);
    fputc('}', f);
  }
  fputs("]", f);

  fprintf(f, ", \"sane\": %s, \"ok\": %s}\n", sane ? "true" : "false", ok ? "true" : "false");
  fflush(f);
}

/* ---------------------------------------------------------------------------------------------- */
/* DDS                                                                                            */

typedef struct {
  const char *name;
  dds_entity_t reader;
} reader_t;

static dds_entity_t make_topic(dds_entity_t pp, const dds_topic_descriptor_t *desc, const char *name) {
  dds_entity_t t = dds_create_topic(pp, desc, name, NULL, NULL);
  if (t < 0) fprintf(stderr, "hadal-ros2-probe: dds_create_topic(%s): %s\n", name, dds_strretcode(-t));
  return t;
}

/* depth 0: KEEP_ALL. */
static dds_entity_t make_reader(dds_entity_t pp, dds_entity_t topic, bool reliable, int32_t depth) {
  dds_qos_t *qos = dds_create_qos();
  if (reliable) dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  else dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
  if (depth > 0) dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, depth);
  else dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
  dds_entity_t rd = dds_create_reader(pp, topic, qos, NULL);
  dds_delete_qos(qos);
  if (rd < 0) fprintf(stderr, "hadal-ros2-probe: dds_create_reader: %s\n", dds_strretcode(-rd));
  return rd;
}

static void update_reader_match(endpoint_stats_t *e, dds_entity_t rd, double t) {
  dds_subscription_matched_status_t st;
  if (dds_get_subscription_matched_status(rd, &st) != DDS_RETCODE_OK) return;
  e->matched_now = st.current_count;
  if (st.total_count > 0 && e->first_match_s < 0) e->first_match_s = t;
}

static void update_writer_match(endpoint_stats_t *e, dds_entity_t wr, double t) {
  dds_publication_matched_status_t st;
  if (dds_get_publication_matched_status(wr, &st) != DDS_RETCODE_OK) return;
  e->matched_now = st.current_count;
  if (st.total_count > 0 && e->first_match_s < 0) e->first_match_s = t;
}

static bool guid_prefix_equal(const dds_guid_t *a, const dds_guid_t *b) {
  return memcmp(a->v, b->v, 12) == 0;
}

static void note_remote_publication(stats_t *s, const dds_guid_t *own, const dds_builtintopic_endpoint_t *ep) {
  if (guid_prefix_equal(&ep->participant_key, own)) return;
  if (ep->topic_name == NULL || strncmp(ep->topic_name, "rt/", 3) != 0) return;
  for (size_t i = 0; i < s->n_remote; ++i)
    if (strcmp(s->remote[i].topic, ep->topic_name) == 0 &&
        strcmp(s->remote[i].type, ep->type_name ? ep->type_name : "") == 0)
      return;
  if (s->n_remote == MAX_REMOTE) return;
  copy_str(s->remote[s->n_remote].topic, sizeof(s->remote[0].topic), ep->topic_name);
  copy_str(s->remote[s->n_remote].type, sizeof(s->remote[0].type), ep->type_name);
  ++s->n_remote;
}

enum which { W_CLOCK, W_ODOM_REL, W_ODOM_BE, W_THRUSTER, W_STATUS, W_BUILTIN, W_COUNT };

/* Takes everything available from reader `w`; returns the number of valid samples. */
static unsigned long drain(enum which w, dds_entity_t rd, stats_t *s, const options_t *o, const dds_guid_t *own,
                           double t) {
  void *samples[TAKE_BATCH];
  dds_sample_info_t infos[TAKE_BATCH];
  unsigned long valid = 0;
  for (;;) {
    memset(samples, 0, sizeof(samples)); /* NULL buffers: Cyclone loans the samples */
    int32_t n = dds_take(rd, samples, infos, TAKE_BATCH, TAKE_BATCH);
    if (n <= 0) break;
    for (int32_t i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      ++valid;
      switch (w) {
        case W_CLOCK: on_clock(s, samples[i]); break;
        case W_ODOM_REL: on_odometry(s, samples[i], true); break;
        case W_ODOM_BE: on_odometry(s, samples[i], false); break;
        case W_THRUSTER: on_thruster_state(s, o, samples[i]); break;
        case W_STATUS: on_status(s, samples[i]); break;
        case W_BUILTIN: note_remote_publication(s, own, samples[i]); break;
        default: break;
      }
    }
    dds_return_loan(rd, samples, n);
    if (n < TAKE_BATCH) break;
  }
  endpoint_stats_t *e = NULL;
  switch (w) {
    case W_CLOCK: e = &s->clock; break;
    case W_ODOM_REL: e = &s->odom_reliable; break;
    case W_ODOM_BE: e = &s->odom_best_effort; break;
    case W_THRUSTER: e = &s->thruster_state; break;
    case W_STATUS: e = &s->status; break;
    default: break;
  }
  if (e != NULL && valid > 0) {
    if (e->count == 0) e->first_sample_s = t;
    e->count += valid;
  }
  return valid;
}

/* Takes everything available from a sensor reader; only the reliable reader's samples are decoded. */
static unsigned long drain_sensor(enum sensor_kind k, bool reliable, dds_entity_t rd, stats_t *s, double t) {
  void *samples[TAKE_BATCH];
  dds_sample_info_t infos[TAKE_BATCH];
  unsigned long valid = 0;
  sensor_stats_t *m = &s->sensors[k];
  for (;;) {
    memset(samples, 0, sizeof(samples));
    int32_t n = dds_take(rd, samples, infos, TAKE_BATCH, TAKE_BATCH);
    if (n <= 0) break;
    for (int32_t i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      ++valid;
      if (reliable) on_sensor_sample(k, m, samples[i]);
    }
    dds_return_loan(rd, samples, n);
    if (n < TAKE_BATCH) break;
  }
  endpoint_stats_t *e = reliable ? &m->reliable : &m->best_effort;
  if (valid > 0) {
    if (e->count == 0) e->first_sample_s = t;
    e->count += valid;
  }
  return valid;
}

int main(int argc, char **argv) {
  options_t o;
  if (parse_options(argc, argv, &o) != 0) {
    usage(stderr);
    return 2;
  }
  const double t0 = now_s();
  const double t0_unix = unix_now_s(); /* lets a driver relate the probe's times to other processes */
  static char xml[2048];
  const char *config_source = configure_discovery(&o, xml, sizeof(xml));

  struct sigaction sa;
  memset(&sa, 0, sizeof(sa));
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);

  stats_t s;
  memset(&s, 0, sizeof(s));
  endpoint_init(&s.clock);
  endpoint_init(&s.odom_reliable);
  endpoint_init(&s.odom_best_effort);
  endpoint_init(&s.thruster_state);
  endpoint_init(&s.status);
  endpoint_init(&s.setpoint_writer);
  for (int k = 0; k < S_COUNT; ++k) {
    endpoint_init(&s.sensors[k].reliable);
    endpoint_init(&s.sensors[k].best_effort);
  }
  s.clock_non_decreasing = true;

  dds_entity_t pp = dds_create_participant((dds_domainid_t)o.domain, NULL, NULL);
  if (pp < 0) {
    fprintf(stderr, "hadal-ros2-probe: dds_create_participant(%d): %s\n", o.domain, dds_strretcode(-pp));
    return 2;
  }
  dds_guid_t own_guid;
  memset(&own_guid, 0, sizeof(own_guid));
  dds_get_guid(pp, &own_guid);

  char odom_name[256], thruster_state_name[256], setpoints_name[256];
  snprintf(odom_name, sizeof(odom_name), "rt/%s/odometry", o.vehicle);
  snprintf(thruster_state_name, sizeof(thruster_state_name), "rt/%s/thrusters/state", o.vehicle);
  snprintf(setpoints_name, sizeof(setpoints_name), "rt/%s/actuators/commands", o.vehicle);

  dds_entity_t t_clock = make_topic(pp, &rosgraph_msgs_msg_dds__Clock__desc, "rt/clock");
  dds_entity_t t_odom = make_topic(pp, &nav_msgs_msg_dds__Odometry__desc, odom_name);
  dds_entity_t t_thr = make_topic(pp, &hadal_msgs_msg_dds__ThrusterState__desc, thruster_state_name);
  dds_entity_t t_status = make_topic(pp, &hadal_msgs_msg_dds__SimStatus__desc, "rt/hadal/status");
  if (t_clock < 0 || t_odom < 0 || t_thr < 0 || t_status < 0) return 2;

  dds_entity_t rd[W_COUNT];
  rd[W_CLOCK] = make_reader(pp, t_clock, true, 100);
  rd[W_ODOM_REL] = make_reader(pp, t_odom, true, 100);
  rd[W_ODOM_BE] = make_reader(pp, t_odom, false, 5); /* rclcpp SensorDataQoS: best effort, depth 5 */
  rd[W_THRUSTER] = make_reader(pp, t_thr, true, 100);
  rd[W_STATUS] = make_reader(pp, t_status, true, 10);
  rd[W_BUILTIN] = dds_create_reader(pp, DDS_BUILTIN_TOPIC_DCPSPUBLICATION, NULL, NULL);
  for (int i = 0; i < W_COUNT; ++i)
    if (rd[i] < 0) return 2;

  /* Sensors: a reliable KEEP_ALL reader counts and decodes every sample; a best-effort one (rclcpp
   * SensorDataQoS) shows that a typical ROS 2 sensor subscription matches too. */
  static char sensor_topics[S_COUNT][256];
  dds_entity_t rd_sensor[S_COUNT][2]; /* [k][0] reliable, [k][1] best effort */
  for (int k = 0; k < S_COUNT; ++k) {
    rd_sensor[k][0] = rd_sensor[k][1] = 0;
    snprintf(sensor_topics[k], sizeof(sensor_topics[k]), "rt/%s/%s", o.vehicle, k_sensors[k].name);
    if (!sensor_enabled(&o, k)) continue;
    dds_entity_t topic = make_topic(pp, k_sensors[k].desc, sensor_topics[k]);
    if (topic < 0) return 2;
    rd_sensor[k][0] = make_reader(pp, topic, true, 0);
    rd_sensor[k][1] = make_reader(pp, topic, false, 5);
    if (rd_sensor[k][0] < 0 || rd_sensor[k][1] < 0) return 2;
  }

  dds_entity_t wr = 0;
  std_msgs_msg_dds__Float64MultiArray_ cmd;
  std_msgs_msg_dds__MultiArrayDimension_ dim;
  memset(&cmd, 0, sizeof(cmd));
  if (o.publish) {
    dds_entity_t t_sp = make_topic(pp, &std_msgs_msg_dds__Float64MultiArray__desc, setpoints_name);
    if (t_sp < 0) return 2;
    dds_qos_t *qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 10);
    wr = dds_create_writer(pp, t_sp, qos, NULL);
    dds_delete_qos(qos);
    if (wr < 0) {
      fprintf(stderr, "hadal-ros2-probe: dds_create_writer(%s): %s\n", setpoints_name, dds_strretcode(-wr));
      return 2;
    }
    dim.label = "thrusters";
    dim.size = (uint32_t)o.n_setpoints;
    dim.stride = (uint32_t)o.n_setpoints;
    cmd.layout.dim._maximum = 1;
    cmd.layout.dim._length = 1;
    cmd.layout.dim._buffer = &dim;
    cmd.layout.dim._release = false;
    cmd.layout.data_offset = 0;
    cmd.data._maximum = (uint32_t)o.n_setpoints;
    cmd.data._length = (uint32_t)o.n_setpoints;
    cmd.data._buffer = o.setpoints;
    cmd.data._release = false;
  }

  dds_entity_t ws = dds_create_waitset(pp);
  for (int i = 0; i < W_COUNT; ++i) {
    dds_entity_t cond = dds_create_readcondition(rd[i], DDS_ANY_STATE);
    dds_waitset_attach(ws, cond, (dds_attach_t)i);
  }
  for (int k = 0; k < S_COUNT; ++k)
    for (int j = 0; j < 2 && sensor_enabled(&o, k); ++j)
      dds_waitset_attach(ws, dds_create_readcondition(rd_sensor[k][j], DDS_ANY_STATE),
                         (dds_attach_t)(W_COUNT + 2 * k + j));

  /* Everything exists: a driver can start the server now. */
  fprintf(stderr, "hadal-ros2-probe: ready (domain %d, %s)\n", o.domain, config_source);
  fflush(stderr);

  const double period = 1.0 / o.rate_hz;
  double next_write = now_s() - t0;
  const char *stop_reason = "time limit";
  s.last_sample_s = -1.0;
  for (;;) {
    double t = now_s() - t0;
    if (g_stop) {
      stop_reason = "signal";
      break;
    }
    if (t >= o.seconds) {
      stop_reason = "time limit";
      break;
    }
    double wait = 0.05;
    if (o.publish && next_write - t < wait) wait = next_write - t;
    if (o.seconds - t < wait) wait = o.seconds - t;
    if (wait > 0) dds_waitset_wait(ws, NULL, 0, DDS_SECS(wait));

    t = now_s() - t0;
    for (int i = 0; i < W_COUNT; ++i) {
      unsigned long got = drain((enum which)i, rd[i], &s, &o, &own_guid, t);
      if (got > 0 && (i == W_CLOCK || i == W_ODOM_REL || i == W_ODOM_BE)) s.last_sample_s = t;
    }
    update_reader_match(&s.clock, rd[W_CLOCK], t);
    update_reader_match(&s.odom_reliable, rd[W_ODOM_REL], t);
    update_reader_match(&s.odom_best_effort, rd[W_ODOM_BE], t);
    update_reader_match(&s.thruster_state, rd[W_THRUSTER], t);
    update_reader_match(&s.status, rd[W_STATUS], t);
    for (int k = 0; k < S_COUNT; ++k) {
      if (!sensor_enabled(&o, k)) continue;
      for (int j = 0; j < 2; ++j)
        if (drain_sensor((enum sensor_kind)k, j == 0, rd_sensor[k][j], &s, t) > 0) s.last_sample_s = t;
      update_reader_match(&s.sensors[k].reliable, rd_sensor[k][0], t);
      update_reader_match(&s.sensors[k].best_effort, rd_sensor[k][1], t);
    }
    if (o.publish) {
      update_writer_match(&s.setpoint_writer, wr, t);
      if (t >= next_write) {
        dds_return_t rc = dds_write(wr, &cmd);
        if (rc == DDS_RETCODE_OK) ++s.setpoint_writer.count;
        else fprintf(stderr, "hadal-ros2-probe: dds_write(%s): %s\n", setpoints_name, dds_strretcode(-rc));
        next_write += period;
        if (next_write < t) next_write = t + period; /* do not burst after a stall */
      }
    }
    const bool seen_both = s.clock.count > 0 && s.odom_reliable.count > 0;
    if (o.enough > 0 && s.clock.count >= o.enough && s.odom_reliable.count >= o.enough) {
      stop_reason = "enough samples";
      break;
    }
    if (o.idle_s > 0 && seen_both && t - s.last_sample_s >= o.idle_s) {
      stop_reason = "idle (publisher gone quiet)";
      break;
    }
  }
  const double elapsed = now_s() - t0;

  const bool ok = s.clock.count > 0 && s.odom_reliable.count > 0;
  const bool sane = ok && s.odom_insane == 0 && s.clock_non_decreasing && s.odom_frame_id[0] != '\0' &&
                    s.odom_child_frame_id[0] != '\0';
  print_report(&o, &s, sensor_topics, config_source, t0_unix, elapsed, stop_reason, sane, ok);

  dds_delete(pp);
  return ok ? 0 : 1;
}
