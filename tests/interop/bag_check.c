/* hadal-bag-check: decodes every message of a rosbag2 bag (sqlite3 storage) with the ROS 2 types of
 * ros2_types.idl, through Cyclone DDS's CDR deserialiser, independently of Hadal's own IDL and of Fast DDS.
 *
 * Why: hadald and hadal-record write each sample's CDR bytes as they came off the wire into the bag
 * (docs/recording.md), with the ROS 2 topic and type names `ros2 bag play`
 * will use to pick a deserialiser. A bag is only useful to ROS 2 if every blob really is an instance of
 * the type its topic names, in ROS 2's layout (final extensibility, plain XCDR1). The Cyclone probes
 * (ros2_probe.c, ros2_lockstep_probe.c) check live topics; this checks what ended up in the file,
 * including the camera topics the probes never read.
 *
 * What it checks (each failure names the topic and the message's index in it, and the exit status is 1):
 *   - the bag's databases: those metadata.yaml lists under relative_file_paths (or, without a
 *     metadata.yaml, every *.db3 in BAG_DIR); metadata.yaml's per-topic message_count, its total and its
 *     topic types agree with the databases;
 *   - every topic: serialization_format "cdr", and a ROS 2 type name ("pkg/msg/Type") whose DDS name
 *     ("pkg::msg::dds_::Type_", the ROS 2 mapping) is a type of ros2_types.idl;
 *   - every message: a plain CDR (XCDR1) encapsulation header, a payload that Cyclone's validating
 *     normaliser (dds_stream_normalize_data) accepts for that type, and one whose length is what the type
 *     consumed, give or take the 0-3 bytes of padding to a multiple of 4 (which the encapsulation options'
 *     low two bits may state); a blob of another type, or a truncated one, fails one of these. The
 *     payload is then read into the IDL's C struct (dds_stream_read) and checked where it is cheap:
 *     header stamps valid (nanosec < 1e9) and non-decreasing per topic, booleans 0 or 1, Image
 *     data = step * height bytes, CameraInfo's distortion vector as long as its model wants, LaserScan
 *     ranges one per beam, sonar images as many samples as beams x bins, a multibeam's arrays one per beam, per-actuator arrays of the hadal_msgs states as long as their name list, ...
 *
 * Prints one JSON object on stdout: per topic its type, message count, decoded count, the first and last
 * stamp, the frame_id and a few values of its last message. Exit status 0: all good; 1: a check failed
 * (each failure also on stderr); 2: usage error.
 *
 * usage: hadal-bag-check [--allow-time-resets] BAG_DIR
 *   --allow-time-resets  stamps may go back (a lockstep run reset to sim time 0 during the recording)
 */
#define _POSIX_C_SOURCE 200809L

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <sqlite3.h>

#include "dds/dds.h"
#include "dds/ddsi/ddsi_cdrstream.h"
#include "ros2_types.h"

#define MAX_ERRORS_PER_TOPIC 5
#define MAX_ERRORS_IN_JSON 50
#define SUMMARY_LEN 512

/* ---------------------------------------------------------------------------------------------- */
/* Small helpers                                                                                  */

static char *xstrdup(const char *s) {
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d == NULL) {
    fprintf(stderr, "hadal-bag-check: out of memory\n");
    exit(1);
  }
  memcpy(d, s, n);
  return d;
}

static void *xcalloc(size_t n, size_t size) {
  void *p = calloc(n == 0 ? 1 : n, size == 0 ? 1 : size);
  if (p == NULL) {
    fprintf(stderr, "hadal-bag-check: out of memory\n");
    exit(1);
  }
  return p;
}

static void *xrealloc(void *p, size_t size) {
  void *q = realloc(p, size == 0 ? 1 : size);
  if (q == NULL) {
    fprintf(stderr, "hadal-bag-check: out of memory\n");
    exit(1);
  }
  return q;
}

/* Length of the well-formed UTF-8 sequence at p (1-4), or 0 if it is not one. */
static size_t utf8_length(const unsigned char *p) {
  size_t n = p[0] < 0x80 ? 1 : (p[0] & 0xe0) == 0xc0 ? 2 : (p[0] & 0xf0) == 0xe0 ? 3 : (p[0] & 0xf8) == 0xf0 ? 4 : 0;
  if (n == 0 || (n == 2 && p[0] < 0xc2)) return 0;
  for (size_t i = 1; i < n; ++i)
    if ((p[i] & 0xc0) != 0x80) return 0;
  return n;
}

/* A JSON string; bytes that are not UTF-8 (a corrupt frame_id, say) become U+FFFD. */
static void json_string(FILE *out, const char *s) {
  fputc('"', out);
  for (const unsigned char *p = (const unsigned char *)s; *p != '\0';) {
    size_t n = utf8_length(p);
    if (*p == '"' || *p == '\\') {
      fprintf(out, "\\%c", *p);
    } else if (*p < 0x20) {
      fprintf(out, "\\u%04x", *p);
    } else if (n == 0) {
      fputs("\\ufffd", out);
      n = 1;
    } else {
      fwrite(p, 1, n, out);
    }
    p += n == 0 ? 1 : n;
  }
  fputc('"', out);
}

/* A JSON number into buf (32 bytes), or null for NaN and infinities (JSON has neither). */
static const char *num(double v, char *buf) {
  if (isfinite(v)) {
    snprintf(buf, 32, "%.9g", v);
  } else {
    snprintf(buf, 32, "null");
  }
  return buf;
}

/* Appends printf-style text to a fixed buffer (a message's summary), truncating silently. */
static void appendf(char *buf, size_t size, const char *fmt, ...) {
  size_t used = strlen(buf);
  if (used + 1 >= size) return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf + used, size - used, fmt, ap);
  va_end(ap);
}

/* A string for a JSON summary, in printable ASCII: other bytes, quotes and backslashes become '?'. */
static const char *plain(const char *s, char *buf, size_t size) {
  size_t i = 0;
  for (; s != NULL && s[i] != '\0' && i + 1 < size; ++i) {
    unsigned char c = (unsigned char)s[i];
    buf[i] = (c == '"' || c == '\\' || c < 0x20 || c > 0x7e) ? '?' : (char)c;
  }
  buf[i] = '\0';
  return buf;
}

/* ---------------------------------------------------------------------------------------------- */
/* Per-type checks: return NULL when the decoded sample is sane, else why not (into why).         */
/* summarize writes a JSON object's members (no braces) describing the sample.                    */

typedef const char *(*check_fn)(const void *sample, char *why, size_t why_size);
typedef void (*summary_fn)(const void *sample, char *out, size_t size);

/* A boolean's byte must be 0 or 1 (Cyclone's normaliser does not look); read as bytes, not as bool. */
static bool bool_bytes_ok(const void *p, size_t n) {
  const unsigned char *b = p;
  for (size_t i = 0; i < n; ++i)
    if (b[i] > 1) return false;
  return true;
}

static double quat_norm(const geometry_msgs_msg_dds__Quaternion_ *q) {
  return sqrt(q->x * q->x + q->y * q->y + q->z * q->z + q->w * q->w);
}

static const char *check_odometry(const void *s, char *why, size_t n) {
  const nav_msgs_msg_dds__Odometry_ *m = s;
  double norm = quat_norm(&m->pose.pose.orientation);
  if (!(fabs(norm - 1.0) < 1e-3)) {
    snprintf(why, n, "pose.pose.orientation is not a unit quaternion (norm %g)", norm);
    return why;
  }
  return NULL;
}

static void summarize_odometry(const void *s, char *out, size_t n) {
  const nav_msgs_msg_dds__Odometry_ *m = s;
  char b[128], x[32], y[32], z[32];
  const geometry_msgs_msg_dds__Point_ *p = &m->pose.pose.position;
  snprintf(out, n, "\"child_frame_id\": \"%s\", \"position\": [%s, %s, %s]", plain(m->child_frame_id, b, sizeof b),
           num(p->x, x), num(p->y, y), num(p->z, z));
}

static const char *check_joint_state(const void *s, char *why, size_t n) {
  const sensor_msgs_msg_dds__JointState_ *m = s;
  const uint32_t joints = m->name._length;
  if (m->position._length != joints || m->velocity._length != joints || m->effort._length != joints) {
    snprintf(why, n, "%u names but %u positions, %u velocities and %u efforts", (unsigned)joints,
             (unsigned)m->position._length, (unsigned)m->velocity._length, (unsigned)m->effort._length);
    return why;
  }
  for (uint32_t k = 0; k < joints; ++k) {
    if (!isfinite(m->position._buffer[k]) || !isfinite(m->velocity._buffer[k]) || !isfinite(m->effort._buffer[k])) {
      snprintf(why, n, "joint %u is not finite", (unsigned)k);
      return why;
    }
  }
  return NULL;
}

static const char *check_wrench_stamped(const void *s, char *why, size_t n) {
  const geometry_msgs_msg_dds__WrenchStamped_ *m = s;
  const geometry_msgs_msg_dds__Vector3_ *f = &m->wrench.force, *t = &m->wrench.torque;
  if (!isfinite(f->x) || !isfinite(f->y) || !isfinite(f->z) || !isfinite(t->x) || !isfinite(t->y) || !isfinite(t->z)) {
    snprintf(why, n, "a force or torque that is not finite");
    return why;
  }
  return NULL;
}

static const char *check_imu(const void *s, char *why, size_t n) {
  const sensor_msgs_msg_dds__Imu_ *m = s;
  /* orientation_covariance[0] = -1: no orientation estimate; otherwise the quaternion must be one. */
  if (m->orientation_covariance[0] != -1.0 && !(fabs(quat_norm(&m->orientation) - 1.0) < 1e-3)) {
    snprintf(why, n, "orientation is reported (covariance[0] %g) but not a unit quaternion",
             m->orientation_covariance[0]);
    return why;
  }
  return NULL;
}

static void summarize_fluid_pressure(const void *s, char *out, size_t n) {
  const sensor_msgs_msg_dds__FluidPressure_ *m = s;
  char v[32];
  snprintf(out, n, "\"fluid_pressure\": %s", num(m->fluid_pressure, v));
}

static const char *check_nav_sat_fix(const void *s, char *why, size_t n) {
  const sensor_msgs_msg_dds__NavSatFix_ *m = s;
  /* NavSatStatus.msg: STATUS_NO_FIX -1 .. STATUS_GBAS_FIX 2; NavSatFix.msg: COVARIANCE_TYPE_* 0..3. */
  if (m->status.status < -1 || m->status.status > 2 || m->position_covariance_type > 3) {
    snprintf(why, n, "status.status %d or position_covariance_type %u out of range", m->status.status,
             m->position_covariance_type);
    return why;
  }
  return NULL;
}

static const char *check_range(const void *s, char *why, size_t n) {
  const sensor_msgs_msg_dds__Range_ *m = s;
  if (m->radiation_type > 1) { /* Range.msg: ULTRASOUND 0, INFRARED 1 */
    snprintf(why, n, "radiation_type %u is neither ULTRASOUND (0) nor INFRARED (1)", m->radiation_type);
    return why;
  }
  /* The limits are distances (range itself may be -inf / +inf outside them). */
  if (!(m->field_of_view >= 0.0f && m->field_of_view <= 6.2832f) ||
      !(m->min_range >= 0.0f && m->min_range <= m->max_range && isfinite(m->max_range))) {
    snprintf(why, n, "field_of_view %g rad, min_range %g m, max_range %g m: not a beam width and two limits",
             (double)m->field_of_view, (double)m->min_range, (double)m->max_range);
    return why;
  }
  return NULL;
}

static void summarize_range(const void *s, char *out, size_t n) {
  const sensor_msgs_msg_dds__Range_ *m = s;
  char v[32];
  snprintf(out, n, "\"range\": %s", num(m->range, v));
}

static const char *check_dvl(const void *s, char *why, size_t n) {
  const marine_acoustic_msgs_msg_dds__Dvl_ *m = s;
  if (!bool_bytes_ok(&m->beam_ranges_valid, 1) || !bool_bytes_ok(&m->beam_velocities_valid, 1)) {
    snprintf(why, n, "beam_ranges_valid or beam_velocities_valid is neither 0 nor 1");
    return why;
  }
  if (m->num_good_beams > 4) {
    snprintf(why, n, "num_good_beams %u of 4 beams", m->num_good_beams);
    return why;
  }
  return NULL;
}

static const char *check_laser_scan(const void *s, char *why, size_t n) {
  const sensor_msgs_msg_dds__LaserScan_ *m = s;
  uint32_t beams = m->ranges._length;
  if (m->intensities._length != 0 && m->intensities._length != beams) {
    snprintf(why, n, "%u intensities for %u ranges", m->intensities._length, beams);
    return why;
  }
  if (m->angle_increment != 0.0f && beams > 0) {
    double span = ((double)m->angle_max - (double)m->angle_min) / (double)m->angle_increment;
    if (!(fabs(span - (double)(beams - 1)) <= 0.51)) {
      snprintf(why, n, "%u ranges, but angle_min %g .. angle_max %g in steps of %g makes %.2f beams", beams,
               (double)m->angle_min, (double)m->angle_max, (double)m->angle_increment, span + 1.0);
      return why;
    }
  }
  return NULL;
}

static void summarize_laser_scan(const void *s, char *out, size_t n) {
  const sensor_msgs_msg_dds__LaserScan_ *m = s;
  char lo[32], hi[32];
  snprintf(out, n, "\"beams\": %u, \"angle_min\": %s, \"angle_max\": %s", m->ranges._length, num(m->angle_min, lo),
           num(m->angle_max, hi));
}

/* The sonars' messages: sample arrays as long as their beams and bins say (1 byte per sample for dtype uint8,
 * 4 for float32), per-beam arrays as long as each other. */
static unsigned sonar_sample_bytes(uint32_t dtype) { return dtype == 0 || dtype == 1 ? 1 : dtype == 8 ? 4 : 0; }

static const char *check_projected_sonar_image(const void *s, char *why, size_t n) {
  const marine_acoustic_msgs_msg_dds__ProjectedSonarImage_ *m = s;
  const unsigned size = sonar_sample_bytes(m->image.dtype);
  const uint64_t expected = (uint64_t)m->beam_directions._length * m->ranges._length * size;
  if (m->image.beam_count != m->beam_directions._length || size == 0 || m->image.data._length != expected) {
    snprintf(why, n, "%u beam directions, %u ranges, image of %u beams, dtype %u, %u bytes", m->beam_directions._length,
             m->ranges._length, m->image.beam_count, m->image.dtype, m->image.data._length);
    return why;
  }
  return NULL;
}

static const char *check_raw_sonar_image(const void *s, char *why, size_t n) {
  const marine_acoustic_msgs_msg_dds__RawSonarImage_ *m = s;
  const unsigned size = sonar_sample_bytes(m->image.dtype);
  const uint64_t expected = (uint64_t)m->image.beam_count * m->samples_per_beam * size;
  if (size == 0 || m->image.data._length != expected || m->rx_angles._length != m->image.beam_count) {
    snprintf(why, n, "%u beams x %u samples, dtype %u, %u bytes, %u rx angles", m->image.beam_count,
             m->samples_per_beam, m->image.dtype, m->image.data._length, m->rx_angles._length);
    return why;
  }
  return NULL;
}

static const char *check_sonar_detections(const void *s, char *why, size_t n) {
  const marine_acoustic_msgs_msg_dds__SonarDetections_ *m = s;
  const uint32_t beams = m->flags._length;
  if (m->two_way_travel_times._length != beams || m->tx_delays._length != beams || m->intensities._length != beams ||
      m->tx_angles._length != beams || m->rx_angles._length != beams) {
    snprintf(why, n, "%u flags but %u travel times, %u intensities, %u rx angles", beams,
             m->two_way_travel_times._length, m->intensities._length, m->rx_angles._length);
    return why;
  }
  return NULL;
}

/* Bytes per pixel of the sensor_msgs image encodings Hadal's cameras (and common drivers) use; 0: unknown. */
static unsigned bytes_per_pixel(const char *encoding) {
  static const struct {
    const char *name;
    unsigned bytes;
  } known[] = {{"mono8", 1},   {"8UC1", 1},   {"mono16", 2}, {"16UC1", 2}, {"rgb8", 3},  {"bgr8", 3},   {"8UC3", 3},
               {"rgba8", 4},   {"bgra8", 4},  {"8UC4", 4},   {"32FC1", 4}, {"32SC1", 4}, {"rgb16", 6},  {"bgr16", 6},
               {"rgba16", 8},  {"bgra16", 8}, {"64FC1", 8},  {"32FC3", 12}};
  for (size_t i = 0; i < sizeof(known) / sizeof(known[0]); ++i)
    if (strcmp(encoding, known[i].name) == 0) return known[i].bytes;
  return 0;
}

static const char *check_image(const void *s, char *why, size_t n) {
  const sensor_msgs_msg_dds__Image_ *m = s;
  uint64_t expected = (uint64_t)m->step * m->height;
  if ((uint64_t)m->data._length != expected) {
    snprintf(why, n, "%u data bytes, but step %u x height %u = %llu", m->data._length, m->step, m->height,
             (unsigned long long)expected);
    return why;
  }
  if (m->is_bigendian > 1) {
    snprintf(why, n, "is_bigendian %u is neither 0 nor 1", m->is_bigendian);
    return why;
  }
  if (m->encoding[0] == '\0') {
    snprintf(why, n, "empty encoding");
    return why;
  }
  unsigned bpp = bytes_per_pixel(m->encoding);
  if (bpp != 0 && (uint64_t)m->step < (uint64_t)m->width * bpp) {
    snprintf(why, n, "step %u bytes is shorter than a row of %u %s pixels (%u bytes each)", m->step, m->width,
             m->encoding, bpp);
    return why;
  }
  return NULL;
}

static void summarize_image(const void *s, char *out, size_t n) {
  const sensor_msgs_msg_dds__Image_ *m = s;
  char b[64];
  snprintf(out, n, "\"width\": %u, \"height\": %u, \"encoding\": \"%s\", \"step\": %u, \"data_bytes\": %u", m->width,
           m->height, plain(m->encoding, b, sizeof b), m->step, m->data._length);
}

static const char *check_camera_info(const void *s, char *why, size_t n) {
  const sensor_msgs_msg_dds__CameraInfo_ *m = s;
  /* sensor_msgs/distortion_models.hpp: the coefficient count each model uses. */
  static const struct {
    const char *model;
    uint32_t coefficients;
  } models[] = {{"plumb_bob", 5}, {"rational_polynomial", 8}, {"equidistant", 4}};
  for (size_t i = 0; i < sizeof(models) / sizeof(models[0]); ++i) {
    if (strcmp(m->distortion_model, models[i].model) == 0 && m->d._length != models[i].coefficients) {
      snprintf(why, n, "distortion_model %s with %u coefficients in d (it has %u)", m->distortion_model, m->d._length,
               models[i].coefficients);
      return why;
    }
  }
  /* A calibrated camera (k[0] != 0; CameraInfo.msg: k[0] = 0 means uncalibrated) has k[8] = 1, p[10] = 1. */
  if (m->k[0] != 0.0 && (m->k[8] != 1.0 || m->p[10] != 1.0)) {
    snprintf(why, n, "k[8] = %g and p[10] = %g, expected 1 in a calibrated camera's matrices", m->k[8], m->p[10]);
    return why;
  }
  if (!bool_bytes_ok(&m->roi.do_rectify, 1)) {
    snprintf(why, n, "roi.do_rectify is neither 0 nor 1");
    return why;
  }
  if (m->width != 0 && ((uint64_t)m->roi.x_offset + m->roi.width > m->width ||
                        (uint64_t)m->roi.y_offset + m->roi.height > m->height)) {
    snprintf(why, n, "roi %ux%u at (%u, %u) outside the %ux%u image", m->roi.width, m->roi.height, m->roi.x_offset,
             m->roi.y_offset, m->width, m->height);
    return why;
  }
  return NULL;
}

static void summarize_camera_info(const void *s, char *out, size_t n) {
  const sensor_msgs_msg_dds__CameraInfo_ *m = s;
  char b[64], fx[32], fy[32];
  snprintf(out, n, "\"width\": %u, \"height\": %u, \"distortion_model\": \"%s\", \"fx\": %s, \"fy\": %s", m->width,
           m->height, plain(m->distortion_model, b, sizeof b), num(m->k[0], fx), num(m->k[4], fy));
}

/* The hadal_msgs actuator states: one entry per actuator in every array, command_source a SOURCE_*. */
static const char *check_arrays(const char *what, uint32_t names, const uint32_t *lengths, size_t count,
                                uint8_t command_source, char *why, size_t n) {
  for (size_t i = 0; i < count; ++i) {
    if (lengths[i] != names) {
      snprintf(why, n, "%s: array %zu after name has %u entries for %u names", what, i + 1, lengths[i], names);
      return why;
    }
  }
  if (command_source > 2) { /* ThrusterState.msg: SOURCE_NONE 0, SOURCE_SCHEDULE 1, SOURCE_CLIENT 2 */
    snprintf(why, n, "%s: command_source %u is not a ThrusterState SOURCE_*", what, command_source);
    return why;
  }
  return NULL;
}

static const char *check_thruster_state(const void *s, char *why, size_t n) {
  const hadal_msgs_msg_dds__ThrusterState_ *m = s;
  const uint32_t l[] = {m->setpoint._length, m->rotor_speed._length, m->thrust._length, m->torque._length};
  return check_arrays("ThrusterState", m->name._length, l, 4, m->command_source, why, n);
}

static void summarize_names(const dds_sequence_string *names, char *out, size_t n) {
  char b[64];
  appendf(out, n, "\"names\": [");
  for (uint32_t i = 0; i < names->_length; ++i)
    appendf(out, n, "%s\"%s\"", i ? ", " : "", plain(names->_buffer[i], b, sizeof b));
  appendf(out, n, "]");
}

static void summarize_thruster_state(const void *s, char *out, size_t n) {
  const hadal_msgs_msg_dds__ThrusterState_ *m = s;
  out[0] = '\0';
  summarize_names(&m->name, out, n);
  appendf(out, n, ", \"command_source\": %u", m->command_source);
}

static const char *check_track_state(const void *s, char *why, size_t n) {
  const hadal_msgs_msg_dds__TrackState_ *m = s;
  const uint32_t l[] = {m->setpoint._length,     m->belt_speed._length, m->sprocket_speed._length,
                        m->motor_torque._length, m->current._length,    m->power._length,
                        m->load._length};
  return check_arrays("TrackState", m->name._length, l, 7, m->command_source, why, n);
}

static const char *check_fin_state(const void *s, char *why, size_t n) {
  const hadal_msgs_msg_dds__FinState_ *m = s;
  const uint32_t l[] = {m->setpoint._length, m->angle._length, m->attack_angle._length, m->lift._length,
                        m->drag._length};
  return check_arrays("FinState", m->name._length, l, 5, m->command_source, why, n);
}

static const char *check_buoyancy_engine_state(const void *s, char *why, size_t n) {
  const hadal_msgs_msg_dds__BuoyancyEngineState_ *m = s;
  const uint32_t l[] = {m->setpoint._length, m->volume_change._length, m->volume_rate._length,
                        m->force._length,    m->power._length,         m->energy._length};
  return check_arrays("BuoyancyEngineState", m->name._length, l, 6, m->command_source, why, n);
}

static const char *check_drop_weight_state(const void *s, char *why, size_t n) {
  const hadal_msgs_msg_dds__DropWeightState_ *m = s;
  const uint32_t l[] = {m->attached._length, m->reason._length, m->release_time._length, m->force._length};
  const char *bad = check_arrays("DropWeightState", m->name._length, l, 4, m->command_source, why, n);
  if (bad != NULL) return bad;
  if (!bool_bytes_ok(m->attached._buffer, m->attached._length)) {
    snprintf(why, n, "an attached flag is neither 0 nor 1");
    return why;
  }
  for (uint32_t i = 0; i < m->reason._length; ++i) {
    if (m->reason._buffer[i] > hadal_msgs_msg_DropWeightState_Constants_RELEASE_TIME) {
      snprintf(why, n, "reason[%u] = %u is not a RELEASE_*", i, m->reason._buffer[i]);
      return why;
    }
  }
  return NULL;
}

static const char *check_sim_status(const void *s, char *why, size_t n) {
  const hadal_msgs_msg_dds__SimStatus_ *m = s;
  if (m->vehicle_faults._length != m->vehicle_names._length) {
    snprintf(why, n, "%u vehicle_faults for %u vehicle_names", m->vehicle_faults._length, m->vehicle_names._length);
    return why;
  }
  if (m->mode > 2) { /* SimStatus.msg: MODE_REALTIME 0, MODE_FAST 1, MODE_LOCKSTEP 2 */
    snprintf(why, n, "mode %u is not a MODE_*", m->mode);
    return why;
  }
  return NULL;
}

static void summarize_sim_status(const void *s, char *out, size_t n) {
  const hadal_msgs_msg_dds__SimStatus_ *m = s;
  char t[32];
  snprintf(out, n, "\"sim_time\": %s, \"step_count\": %llu, \"mode\": %u, \"rejected_commands\": %llu, ",
           num(m->sim_time, t), (unsigned long long)m->step_count, m->mode, (unsigned long long)m->rejected_commands);
  summarize_names(&m->vehicle_names, out, n);
}

static const char *check_step_reply(const void *s, char *why, size_t n) {
  const hadal_msgs_msg_dds__StepReply_ *m = s;
  uint64_t vehicles = m->vehicle_names._length;
  if (m->poses._length != 7 * vehicles || m->twists._length != 6 * vehicles) {
    snprintf(why, n, "%u poses and %u twists for %llu vehicles (7 and 6 each)", m->poses._length, m->twists._length,
             (unsigned long long)vehicles);
    return why;
  }
  if (!bool_bytes_ok(&m->accepted, 1)) {
    snprintf(why, n, "accepted is neither 0 nor 1");
    return why;
  }
  return NULL;
}

static const char *check_scene(const void *s, char *why, size_t n) {
  const hadal_msgs_msg_dds__Scene_ *m = s;
  if (m->vehicle_types._length != m->vehicle_names._length || !bool_bytes_ok(&m->seabed_is_plane, 1)) {
    snprintf(why, n, "%u vehicle_types for %u vehicle_names, or seabed_is_plane neither 0 nor 1",
             m->vehicle_types._length, m->vehicle_names._length);
    return why;
  }
  for (uint32_t i = 0; i < m->meshes._length; ++i) {
    const hadal_msgs_msg_dds__SceneMesh_ *mesh = &m->meshes._buffer[i];
    uint32_t vertices = mesh->positions._length / 3;
    if (mesh->positions._length % 3 != 0 || mesh->indices._length % 3 != 0) {
      snprintf(why, n, "mesh %u: %u positions and %u indices, not 3 per vertex and per triangle", i,
               mesh->positions._length, mesh->indices._length);
      return why;
    }
    for (uint32_t k = 0; k < mesh->indices._length; ++k) {
      if (mesh->indices._buffer[k] >= vertices) {
        snprintf(why, n, "mesh %u: index %u points past its %u vertices", i, mesh->indices._buffer[k], vertices);
        return why;
      }
    }
  }
  return NULL;
}

/* ---------------------------------------------------------------------------------------------- */
/* The ROS 2 types ros2_types.idl declares                                                        */

typedef enum { STAMP_NONE, STAMP_HEADER, STAMP_CLOCK, STAMP_STEP_REPLY } stamp_kind;

typedef struct {
  const dds_topic_descriptor_t *desc;
  stamp_kind stamp; /* STAMP_HEADER: the struct starts with a std_msgs/Header */
  check_fn check;
  summary_fn summarize;
} known_type;

static const known_type KNOWN_TYPES[] = {
    {&builtin_interfaces_msg_dds__Time__desc, STAMP_NONE, NULL, NULL},
    {&std_msgs_msg_dds__Header__desc, STAMP_HEADER, NULL, NULL},
    {&std_msgs_msg_dds__MultiArrayDimension__desc, STAMP_NONE, NULL, NULL},
    {&std_msgs_msg_dds__MultiArrayLayout__desc, STAMP_NONE, NULL, NULL},
    {&std_msgs_msg_dds__Float64MultiArray__desc, STAMP_NONE, NULL, NULL},
    {&std_msgs_msg_dds__ColorRGBA__desc, STAMP_NONE, NULL, NULL},
    {&rosgraph_msgs_msg_dds__Clock__desc, STAMP_CLOCK, NULL, NULL},
    {&geometry_msgs_msg_dds__Point__desc, STAMP_NONE, NULL, NULL},
    {&geometry_msgs_msg_dds__Vector3__desc, STAMP_NONE, NULL, NULL},
    {&geometry_msgs_msg_dds__Quaternion__desc, STAMP_NONE, NULL, NULL},
    {&geometry_msgs_msg_dds__Pose__desc, STAMP_NONE, NULL, NULL},
    {&geometry_msgs_msg_dds__PoseWithCovariance__desc, STAMP_NONE, NULL, NULL},
    {&geometry_msgs_msg_dds__Twist__desc, STAMP_NONE, NULL, NULL},
    {&geometry_msgs_msg_dds__TwistWithCovariance__desc, STAMP_NONE, NULL, NULL},
    {&geometry_msgs_msg_dds__Wrench__desc, STAMP_NONE, NULL, NULL},
    {&geometry_msgs_msg_dds__WrenchStamped__desc, STAMP_HEADER, check_wrench_stamped, NULL},
    {&geometry_msgs_msg_dds__PoseStamped__desc, STAMP_HEADER, NULL, NULL},
    {&nav_msgs_msg_dds__Odometry__desc, STAMP_HEADER, check_odometry, summarize_odometry},
    {&nav_msgs_msg_dds__Path__desc, STAMP_HEADER, NULL, NULL},
    {&sensor_msgs_msg_dds__FluidPressure__desc, STAMP_HEADER, NULL, summarize_fluid_pressure},
    {&sensor_msgs_msg_dds__Imu__desc, STAMP_HEADER, check_imu, NULL},
    {&sensor_msgs_msg_dds__JointState__desc, STAMP_HEADER, check_joint_state, NULL},
    {&sensor_msgs_msg_dds__MagneticField__desc, STAMP_HEADER, NULL, NULL},
    {&sensor_msgs_msg_dds__NavSatStatus__desc, STAMP_NONE, NULL, NULL},
    {&sensor_msgs_msg_dds__NavSatFix__desc, STAMP_HEADER, check_nav_sat_fix, NULL},
    {&sensor_msgs_msg_dds__Range__desc, STAMP_HEADER, check_range, summarize_range},
    {&sensor_msgs_msg_dds__LaserScan__desc, STAMP_HEADER, check_laser_scan, summarize_laser_scan},
    {&sensor_msgs_msg_dds__Image__desc, STAMP_HEADER, check_image, summarize_image},
    {&sensor_msgs_msg_dds__RegionOfInterest__desc, STAMP_NONE, NULL, NULL},
    {&sensor_msgs_msg_dds__CameraInfo__desc, STAMP_HEADER, check_camera_info, summarize_camera_info},
    {&marine_acoustic_msgs_msg_dds__Dvl__desc, STAMP_HEADER, check_dvl, NULL},
    {&marine_acoustic_msgs_msg_dds__PingInfo__desc, STAMP_NONE, NULL, NULL},
    {&marine_acoustic_msgs_msg_dds__SonarImageData__desc, STAMP_NONE, NULL, NULL},
    {&marine_acoustic_msgs_msg_dds__ProjectedSonarImage__desc, STAMP_HEADER, check_projected_sonar_image, NULL},
    {&marine_acoustic_msgs_msg_dds__RawSonarImage__desc, STAMP_HEADER, check_raw_sonar_image, NULL},
    {&marine_acoustic_msgs_msg_dds__DetectionFlag__desc, STAMP_NONE, NULL, NULL},
    {&marine_acoustic_msgs_msg_dds__SonarDetections__desc, STAMP_HEADER, check_sonar_detections, NULL},
    {&hadal_msgs_msg_dds__ThrusterState__desc, STAMP_HEADER, check_thruster_state, summarize_thruster_state},
    {&hadal_msgs_msg_dds__TrackState__desc, STAMP_HEADER, check_track_state, NULL},
    {&hadal_msgs_msg_dds__FinState__desc, STAMP_HEADER, check_fin_state, NULL},
    {&hadal_msgs_msg_dds__BuoyancyEngineState__desc, STAMP_HEADER, check_buoyancy_engine_state, NULL},
    {&hadal_msgs_msg_dds__DropWeightState__desc, STAMP_HEADER, check_drop_weight_state, NULL},
    {&hadal_msgs_msg_dds__SimStatus__desc, STAMP_HEADER, check_sim_status, summarize_sim_status},
    {&hadal_msgs_msg_dds__AcousticPacket__desc, STAMP_NONE, NULL, NULL},
    {&hadal_msgs_msg_dds__AcousticPackets__desc, STAMP_HEADER, NULL, NULL},
    {&hadal_msgs_msg_dds__UsblFix__desc, STAMP_NONE, NULL, NULL},
    {&hadal_msgs_msg_dds__UsblFixes__desc, STAMP_HEADER, NULL, NULL},
    {&hadal_msgs_msg_dds__LblRange__desc, STAMP_NONE, NULL, NULL},
    {&hadal_msgs_msg_dds__LblRanges__desc, STAMP_HEADER, NULL, NULL},
    {&hadal_msgs_msg_dds__AcousticLink__desc, STAMP_NONE, NULL, NULL},
    {&hadal_msgs_msg_dds__AcousticLinks__desc, STAMP_HEADER, NULL, NULL},
    {&hadal_msgs_msg_dds__WinchState__desc, STAMP_HEADER, NULL, NULL},
    {&hadal_msgs_msg_dds__SeaState__desc, STAMP_HEADER, NULL, NULL},
    {&hadal_msgs_msg_dds__WaveComponent__desc, STAMP_NONE, NULL, NULL},
    {&hadal_msgs_msg_dds__WinchCommand__desc, STAMP_NONE, NULL, NULL},
    {&hadal_msgs_msg_dds__StepRequest__desc, STAMP_NONE, NULL, NULL},
    {&hadal_msgs_msg_dds__StepReply__desc, STAMP_STEP_REPLY, check_step_reply, NULL},
    {&hadal_msgs_msg_dds__SceneMesh__desc, STAMP_NONE, NULL, NULL},
    {&hadal_msgs_msg_dds__SceneFrame__desc, STAMP_NONE, NULL, NULL},
    {&hadal_msgs_msg_dds__Scene__desc, STAMP_HEADER, check_scene, NULL},
};

/* ROS 2's DDS name of a ROS type: "pkg/msg/Type" -> "pkg::msg::dds_::Type_" (what rmw_fastrtps and
 * rmw_cyclonedds register). Returns false for a name not of the form pkg/msg/Type. */
static bool dds_type_name(const char *ros_type, char *out, size_t size) {
  const char *first = strchr(ros_type, '/');
  if (first == NULL || first == ros_type) return false;
  const char *second = strchr(first + 1, '/');
  if (second == NULL || second == first + 1 || second[1] == '\0' || strchr(second + 1, '/') != NULL) return false;
  int n = snprintf(out, size, "%.*s::%.*s::dds_::%s_", (int)(first - ros_type), ros_type, (int)(second - first - 1),
                   first + 1, second + 1);
  return n > 0 && (size_t)n < size;
}

static const known_type *find_type(const char *ros_type) {
  char dds_name[256];
  if (!dds_type_name(ros_type, dds_name, sizeof dds_name)) return NULL;
  for (size_t i = 0; i < sizeof(KNOWN_TYPES) / sizeof(KNOWN_TYPES[0]); ++i)
    if (strcmp(KNOWN_TYPES[i].desc->m_typename, dds_name) == 0) return &KNOWN_TYPES[i];
  return NULL;
}

static const builtin_interfaces_msg_dds__Time_ *stamp_of(const known_type *t, const void *sample) {
  switch (t->stamp) {
    case STAMP_HEADER:
      return &((const std_msgs_msg_dds__Header_ *)sample)->stamp;
    case STAMP_CLOCK:
      return &((const rosgraph_msgs_msg_dds__Clock_ *)sample)->clock;
    case STAMP_STEP_REPLY:
      return &((const hadal_msgs_msg_dds__StepReply_ *)sample)->sim_time;
    case STAMP_NONE:
      break;
  }
  return NULL;
}

/* ---------------------------------------------------------------------------------------------- */
/* Topics of the bag (by name, over all its databases) and the failures found                      */

typedef struct {
  char *name, *type, *format;
  const known_type *known; /* NULL: not in ros2_types.idl */
  long count, decoded;
  long metadata_count; /* -1: not in metadata.yaml */
  char *metadata_type;
  size_t bytes_min, bytes_max;
  bool have_stamp;
  builtin_interfaces_msg_dds__Time_ first_stamp, last_stamp;
  long stamp_regressions;
  char *frame_id;
  long frame_id_changes;
  char summary[SUMMARY_LEN];
  long errors, message_errors;
} topic_t;

typedef struct {
  topic_t *topics;
  size_t n_topics;
  char **errors; /* the first MAX_ERRORS_IN_JSON, for the JSON */
  size_t n_errors;
  long total_errors;
  bool allow_time_resets;
} bag_t;

/* Reports a failure on stderr and in the JSON. A message's failures (message_index >= 0) are reported for
 * the first MAX_ERRORS_PER_TOPIC messages of a topic, then only counted; others always. */
static void fail(bag_t *bag, topic_t *topic, long message_index, const char *fmt, ...) {
  char msg[1024];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  ++bag->total_errors;
  if (topic != NULL) ++topic->errors;
  if (topic != NULL && message_index >= 0 && ++topic->message_errors > MAX_ERRORS_PER_TOPIC) {
    if (topic->message_errors == MAX_ERRORS_PER_TOPIC + 1)
      fprintf(stderr, "hadal-bag-check: FAIL: %s: failures of further messages are only counted\n", topic->name);
    return;
  }
  fprintf(stderr, "hadal-bag-check: FAIL: %s\n", msg);
  if (bag->n_errors < MAX_ERRORS_IN_JSON || message_index < 0) {
    bag->errors = xrealloc(bag->errors, (bag->n_errors + 1) * sizeof(char *));
    bag->errors[bag->n_errors++] = xstrdup(msg);
  }
}

/* A failure of one message: "<topic> message <index in the topic> (<database> row <id>): why". */
static void fail_message(bag_t *bag, topic_t *topic, long index, const char *where, const char *fmt, ...) {
  char why[768];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(why, sizeof why, fmt, ap);
  va_end(ap);
  fail(bag, topic, index, "%s message %ld (%s): %s", topic->name, index, where, why);
}

static topic_t *find_topic(bag_t *bag, const char *name) {
  for (size_t i = 0; i < bag->n_topics; ++i)
    if (strcmp(bag->topics[i].name, name) == 0) return &bag->topics[i];
  return NULL;
}

static topic_t *add_topic(bag_t *bag, const char *name) {
  bag->topics = xrealloc(bag->topics, (bag->n_topics + 1) * sizeof(topic_t));
  topic_t *t = &bag->topics[bag->n_topics++];
  memset(t, 0, sizeof *t);
  t->name = xstrdup(name);
  t->metadata_count = -1;
  return t;
}

/* ---------------------------------------------------------------------------------------------- */
/* metadata.yaml: only what this check needs, in the block layout rosbag2 writes                  */

typedef struct {
  bool present;
  char **files;
  size_t n_files;
  long long message_count; /* -1: absent */
  char *compression_format;
} metadata_t;

static void set_string(char **field, const char *value) {
  free(*field);
  *field = xstrdup(value);
}

static char *trim(char *s) {
  while (*s == ' ' || *s == '\t') ++s;
  size_t n = strlen(s);
  while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\r' || s[n - 1] == '\n')) s[--n] = '\0';
  return s;
}

static char *unquote(char *s) {
  size_t n = strlen(s);
  if (n >= 2 && ((s[0] == '"' && s[n - 1] == '"') || (s[0] == '\'' && s[n - 1] == '\''))) {
    s[n - 1] = '\0';
    return s + 1;
  }
  return s;
}

/* Returns false (after a failure) when metadata.yaml exists but cannot be used. */
static bool read_metadata(bag_t *bag, const char *dir, metadata_t *md) {
  memset(md, 0, sizeof *md);
  md->message_count = -1;
  char path[4096];
  snprintf(path, sizeof path, "%s/metadata.yaml", dir);
  FILE *f = fopen(path, "r");
  if (f == NULL) return true;
  md->present = true;
  char line[4096], section[64] = "", sub[64] = "";
  topic_t *current = NULL;
  while (fgets(line, sizeof line, f) != NULL) {
    size_t indent = strspn(line, " ");
    char *s = trim(line);
    if (*s == '\0' || *s == '#') continue;
    if (indent == 0) { /* a key of rosbag2_bagfile_information (or that key itself) */
      char *colon = strchr(s, ':');
      if (colon == NULL) continue;
      *colon = '\0';
      snprintf(section, sizeof section, "%s", s);
      char *value = unquote(trim(colon + 1));
      if (strcmp(section, "message_count") == 0) md->message_count = strtoll(value, NULL, 10);
      if (strcmp(section, "compression_format") == 0) set_string(&md->compression_format, value);
      continue;
    }
    if (indent == 2 && strncmp(s, "- ", 2) != 0 && strchr(s, ':') != NULL) {
      /* rosbag2 nests everything under rosbag2_bagfile_information: one level in, the bag's keys */
      char *colon = strchr(s, ':');
      *colon = '\0';
      snprintf(section, sizeof section, "%s", s);
      char *value = unquote(trim(colon + 1));
      if (strcmp(section, "message_count") == 0) md->message_count = strtoll(value, NULL, 10);
      if (strcmp(section, "compression_format") == 0) set_string(&md->compression_format, value);
      continue;
    }
    if (strcmp(section, "relative_file_paths") == 0 && strncmp(s, "- ", 2) == 0) {
      md->files = xrealloc(md->files, (md->n_files + 1) * sizeof(char *));
      md->files[md->n_files++] = xstrdup(unquote(trim(s + 2)));
      continue;
    }
    if (strcmp(section, "topics_with_message_count") != 0) continue;
    while (strncmp(s, "- ", 2) == 0) s = trim(s + 2);
    char *colon = strchr(s, ':');
    if (colon == NULL) continue;
    *colon = '\0';
    char *key = s, *value = unquote(trim(colon + 1));
    if (strcmp(key, "topic_metadata") == 0) {
      current = NULL;
      snprintf(sub, sizeof sub, "topic_metadata");
    } else if (strcmp(key, "offered_qos_profiles") == 0) {
      snprintf(sub, sizeof sub, "qos");
    } else if (strcmp(key, "name") == 0 && strcmp(sub, "topic_metadata") == 0) {
      current = find_topic(bag, value);
      if (current != NULL && current->metadata_count >= 0) {
        fail(bag, current, -1, "%s: listed twice in metadata.yaml", value);
      } else if (current == NULL) {
        current = add_topic(bag, value);
      }
      current->metadata_count = 0;
    } else if (strcmp(key, "type") == 0 && strcmp(sub, "topic_metadata") == 0 && current != NULL) {
      set_string(&current->metadata_type, value);
    } else if (strcmp(key, "message_count") == 0 && current != NULL) {
      current->metadata_count = strtol(value, NULL, 10);
      current = NULL;
    }
  }
  fclose(f);
  if (md->n_files == 0) {
    fail(bag, NULL, -1, "%s lists no database under relative_file_paths", path);
    return false;
  }
  if (md->compression_format != NULL && md->compression_format[0] != '\0') {
    fail(bag, NULL, -1, "%s: compression_format %s: compressed bags are not supported", path, md->compression_format);
    return false;
  }
  return true;
}

static int compare_strings(const void *a, const void *b) {
  return strcmp(*(char *const *)a, *(char *const *)b);
}

/* Without metadata.yaml: every *.db3 in the directory, in name order (bag_0.db3, bag_1.db3, ...). */
static void list_databases(const char *dir, metadata_t *md) {
  DIR *d = opendir(dir);
  if (d == NULL) return;
  struct dirent *e;
  while ((e = readdir(d)) != NULL) {
    size_t n = strlen(e->d_name);
    if (n > 4 && strcmp(e->d_name + n - 4, ".db3") == 0) {
      md->files = xrealloc(md->files, (md->n_files + 1) * sizeof(char *));
      md->files[md->n_files++] = xstrdup(e->d_name);
    }
  }
  closedir(d);
  if (md->n_files > 1) qsort(md->files, md->n_files, sizeof(char *), compare_strings);
}

/* ---------------------------------------------------------------------------------------------- */
/* Decoding one message                                                                            */

/* Decodes a message's blob (4-byte encapsulation header + CDR payload) as topic's type; on failure
 * reports it (topic and the message's index in the topic) and returns false. */
static bool decode(bag_t *bag, topic_t *topic, long index, const char *where, const unsigned char *blob,
                   size_t len) {
  const known_type *t = topic->known;
  const char *dds_name = t->desc->m_typename;
  if (len < 4) {
    fail_message(bag, topic, index, where, "%zu bytes, shorter than the 4-byte CDR encapsulation header", len);
    return false;
  }
  /* Encapsulation identifier (big-endian): 0x0000 CDR_BE, 0x0001 CDR_LE, the plain (XCDR1) encodings
   * of ROS 2's final types; PL_CDR, CDR2, D_CDR2 or PL_CDR2 would be another layout. */
  const unsigned encapsulation = ((unsigned)blob[0] << 8) | blob[1];
  const unsigned options = ((unsigned)blob[2] << 8) | blob[3];
  if (encapsulation != 0x0000 && encapsulation != 0x0001) {
    fail_message(bag, topic, index, where, "encapsulation 0x%04x, not plain CDR (0x0000 big or 0x0001 little "
                 "endian, XCDR1) as ROS 2's final types are written", encapsulation);
    return false;
  }
  const bool little = encapsulation == 0x0001;
  const uint16_t probe = 1;
  const bool host_little = *(const unsigned char *)&probe == 1;
  if (len - 4 > UINT32_MAX - 16) {
    fail_message(bag, topic, index, where, "%zu bytes, too large for CDR", len);
    return false;
  }
  const uint32_t size = (uint32_t)(len - 4);
  /* The normaliser works in place (byte swapping) and wants aligned data: a malloc'ed copy. */
  char *payload = xcalloc(1, size);
  memcpy(payload, blob + 4, size);
  uint32_t consumed = 0;
  if (dds_stream_normalize_data(payload, &consumed, size, little != host_little, CDR_ENC_VERSION_1, t->desc->m_ops) ==
      NULL) {
    fail_message(bag, topic, index, where, "does not deserialise as %s (%s): Cyclone's dds_stream_normalize_data "
                 "rejected its %u-byte payload (a field, count or string running past the end, or a string without "
                 "its terminating NUL)", topic->type, dds_name, size);
    free(payload);
    return false;
  }
  /* What the type consumed must be the whole payload, but for padding to a multiple of 4 bytes (which
   * some writers add, stating its length in the options' low two bits). */
  const uint32_t left = size - consumed;
  const uint32_t stated_padding = options & 3u;
  if (left != 0 && (left > 3 || size % 4 != 0)) {
    fail_message(bag, topic, index, where, "%s consumed %u of the payload's %u bytes: %u bytes left over, more than "
                 "the 0-3 bytes of alignment padding (a blob of another type, or a wrong layout?)",
                 dds_name, consumed, size, left);
    free(payload);
    return false;
  }
  if (stated_padding != 0 && left != stated_padding) {
    fail_message(bag, topic, index, where, "the encapsulation options state %u bytes of padding, but %s left %u of "
                 "the %u-byte payload", stated_padding, dds_name, left, size);
    free(payload);
    return false;
  }
  void *sample = xcalloc(1, t->desc->m_size);
  dds_istream_t is;
  dds_istream_init(&is, size, payload, CDR_ENC_VERSION_1);
  dds_stream_read(&is, sample, t->desc->m_ops);
  bool ok = true;
  if (is.m_index != consumed) {
    fail_message(bag, topic, index, where, "Cyclone's reader consumed %u bytes, its validator %u", is.m_index,
                 consumed);
    ok = false;
  }
  dds_istream_fini(&is);

  const builtin_interfaces_msg_dds__Time_ *stamp = ok ? stamp_of(t, sample) : NULL;
  if (stamp != NULL) {
    if (stamp->nanosec >= 1000000000u) {
      fail_message(bag, topic, index, where, "stamp %d s %u ns: nanosec >= 1e9", stamp->sec, stamp->nanosec);
      ok = false;
    } else if (!topic->have_stamp) {
      topic->have_stamp = true;
      topic->first_stamp = topic->last_stamp = *stamp;
    } else {
      const builtin_interfaces_msg_dds__Time_ *last = &topic->last_stamp;
      if (stamp->sec < last->sec || (stamp->sec == last->sec && stamp->nanosec < last->nanosec)) {
        ++topic->stamp_regressions;
        if (!bag->allow_time_resets) {
          fail_message(bag, topic, index, where, "stamp %d.%09u s before the previous message's %d.%09u s",
                       stamp->sec, stamp->nanosec, last->sec, last->nanosec);
          ok = false;
        }
      }
      topic->last_stamp = *stamp;
    }
  }
  if (ok && t->stamp == STAMP_HEADER) {
    const char *frame = ((const std_msgs_msg_dds__Header_ *)sample)->frame_id;
    if (topic->frame_id == NULL) {
      topic->frame_id = xstrdup(frame);
    } else if (strcmp(topic->frame_id, frame) != 0) {
      ++topic->frame_id_changes;
      set_string(&topic->frame_id, frame);
    }
  }
  if (ok && t->check != NULL) {
    char why[512];
    const char *bad = t->check(sample, why, sizeof why);
    if (bad != NULL) {
      fail_message(bag, topic, index, where, "decoded as %s, but not sane: %s", dds_name, bad);
      ok = false;
    }
  }
  if (ok && t->summarize != NULL) {
    topic->summary[0] = '\0';
    t->summarize(sample, topic->summary, sizeof topic->summary);
  }
  dds_stream_free_sample(sample, t->desc->m_ops);
  free(sample);
  free(payload);
  return ok;
}

/* ---------------------------------------------------------------------------------------------- */
/* One database                                                                                    */

typedef struct {
  int64_t id;
  size_t topic; /* index in bag->topics (which add_topic may move) */
} db_topic_t;

static void check_database(bag_t *bag, const char *path, const char *file_name, long long *total) {
  sqlite3 *db = NULL;
  if (sqlite3_open_v2(path, &db, SQLITE_OPEN_READONLY, NULL) != SQLITE_OK) {
    fail(bag, NULL, -1, "%s: cannot open as sqlite3: %s", path, db ? sqlite3_errmsg(db) : "out of memory");
    sqlite3_close(db);
    return;
  }
  sqlite3_stmt *st = NULL;
  if (sqlite3_prepare_v2(db, "SELECT id, name, type, serialization_format FROM topics ORDER BY id", -1, &st, NULL) !=
      SQLITE_OK) {
    fail(bag, NULL, -1, "%s: no rosbag2 topics table: %s", path, sqlite3_errmsg(db));
    sqlite3_close(db);
    return;
  }
  db_topic_t *ids = NULL;
  size_t n_ids = 0;
  while (sqlite3_step(st) == SQLITE_ROW) {
    const char *name = (const char *)sqlite3_column_text(st, 1);
    const char *type = (const char *)sqlite3_column_text(st, 2);
    const char *format = (const char *)sqlite3_column_text(st, 3);
    name = name ? name : "";
    type = type ? type : "";
    format = format ? format : "";
    topic_t *topic = find_topic(bag, name);
    if (topic == NULL) topic = add_topic(bag, name);
    if (topic->type == NULL) {
      topic->type = xstrdup(type);
      topic->format = xstrdup(format);
      topic->known = find_type(type);
      if (strcmp(format, "cdr") != 0)
        fail(bag, topic, -1, "%s: serialization_format \"%s\", not \"cdr\"", name, format);
      if (topic->known == NULL) {
        char dds_name[256];
        if (dds_type_name(type, dds_name, sizeof dds_name)) {
          fail(bag, topic, -1, "%s: type %s (DDS %s) is not a type of ros2_types.idl", name, type, dds_name);
        } else {
          fail(bag, topic, -1, "%s: type \"%s\" is not a ROS 2 type name (pkg/msg/Type)", name, type);
        }
      }
    } else if (strcmp(topic->type, type) != 0 || strcmp(topic->format, format) != 0) {
      fail(bag, topic, -1, "%s: %s in %s, but %s (%s) in an earlier database", name, type, file_name, topic->type,
           topic->format);
    }
    ids = xrealloc(ids, (n_ids + 1) * sizeof *ids);
    ids[n_ids].id = sqlite3_column_int64(st, 0);
    ids[n_ids++].topic = (size_t)(topic - bag->topics);
  }
  sqlite3_finalize(st);

  if (sqlite3_prepare_v2(db, "SELECT id, topic_id, data FROM messages ORDER BY id", -1, &st, NULL) != SQLITE_OK) {
    fail(bag, NULL, -1, "%s: no rosbag2 messages table: %s", path, sqlite3_errmsg(db));
    free(ids);
    sqlite3_close(db);
    return;
  }
  int rc;
  long orphans = 0;
  int64_t first_orphan = 0, first_orphan_topic = 0;
  while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
    ++*total;
    const int64_t row = sqlite3_column_int64(st, 0);
    const int64_t topic_id = sqlite3_column_int64(st, 1);
    topic_t *topic = NULL;
    for (size_t i = 0; i < n_ids && topic == NULL; ++i)
      if (ids[i].id == topic_id) topic = &bag->topics[ids[i].topic];
    if (topic == NULL) {
      if (orphans++ == 0) first_orphan = row, first_orphan_topic = topic_id;
      continue;
    }
    const long index = topic->count++;
    const unsigned char *blob = sqlite3_column_blob(st, 2);
    const size_t len = (size_t)sqlite3_column_bytes(st, 2);
    if (index == 0 || len < topic->bytes_min) topic->bytes_min = len;
    if (len > topic->bytes_max) topic->bytes_max = len;
    if (topic->known == NULL || strcmp(topic->format, "cdr") != 0) continue; /* already reported */
    char where[128];
    snprintf(where, sizeof where, "%s row %lld", file_name, (long long)row);
    if (decode(bag, topic, index, where, blob != NULL ? blob : (const unsigned char *)"", len)) ++topic->decoded;
  }
  if (rc != SQLITE_DONE) fail(bag, NULL, -1, "%s: reading messages: %s", path, sqlite3_errmsg(db));
  if (orphans != 0)
    fail(bag, NULL, -1, "%s: %ld messages of no topic (the first: row %lld, topic_id %lld, not in the topics table)",
         file_name, orphans, (long long)first_orphan, (long long)first_orphan_topic);
  sqlite3_finalize(st);
  free(ids);
  sqlite3_close(db);
}

/* ---------------------------------------------------------------------------------------------- */

static void print_stamp(FILE *out, const builtin_interfaces_msg_dds__Time_ *t) {
  fprintf(out, "%d.%09u", t->sec, t->nanosec);
}

static void print_json(const bag_t *bag, const char *dir, const metadata_t *md, long long total, long long decoded) {
  FILE *out = stdout;
  fputs("{\n  \"bag\": ", out);
  json_string(out, dir);
  fprintf(out, ",\n  \"metadata_yaml\": %s,\n  \"files\": [", md->present ? "true" : "false");
  for (size_t i = 0; i < md->n_files; ++i) {
    if (i) fputs(", ", out);
    json_string(out, md->files[i]);
  }
  fprintf(out, "],\n  \"message_count\": %lld,\n  \"decoded\": %lld,\n  \"topics\": {", total, decoded);
  for (size_t i = 0; i < bag->n_topics; ++i) {
    const topic_t *t = &bag->topics[i];
    fputs(i ? ",\n    " : "\n    ", out);
    json_string(out, t->name);
    fputs(": {\"type\": ", out);
    json_string(out, t->type ? t->type : "");
    fputs(", \"dds_type\": ", out);
    if (t->known) {
      json_string(out, t->known->desc->m_typename);
    } else {
      fputs("null", out);
    }
    fputs(", \"serialization_format\": ", out);
    json_string(out, t->format ? t->format : "");
    fprintf(out, ", \"count\": %ld, \"decoded\": %ld", t->count, t->decoded);
    if (t->metadata_count >= 0) fprintf(out, ", \"metadata_count\": %ld", t->metadata_count);
    fprintf(out, ", \"bytes\": [%zu, %zu]", t->bytes_min, t->bytes_max);
    if (t->have_stamp) {
      fputs(", \"first_stamp\": ", out);
      print_stamp(out, &t->first_stamp);
      fputs(", \"last_stamp\": ", out);
      print_stamp(out, &t->last_stamp);
      fprintf(out, ", \"stamp_regressions\": %ld", t->stamp_regressions);
    }
    if (t->frame_id != NULL) {
      fputs(", \"frame_id\": ", out);
      json_string(out, t->frame_id);
      fprintf(out, ", \"frame_id_changes\": %ld", t->frame_id_changes);
    }
    if (t->summary[0] != '\0') fprintf(out, ", \"last\": {%s}", t->summary);
    fprintf(out, ", \"errors\": %ld}", t->errors);
  }
  fprintf(out, "\n  },\n  \"failures\": %ld,\n  \"errors\": [", bag->total_errors);
  for (size_t i = 0; i < bag->n_errors; ++i) {
    fputs(i ? ",\n    " : "\n    ", out);
    json_string(out, bag->errors[i]);
  }
  fprintf(out, "%s],\n  \"ok\": %s\n}\n", bag->n_errors ? "\n  " : "", bag->total_errors == 0 ? "true" : "false");
}

static void usage(FILE *out) {
  fprintf(out,
          "usage: hadal-bag-check [--allow-time-resets] BAG_DIR\n"
          "  Decodes every message of the rosbag2 (sqlite3) bag BAG_DIR with the ROS 2 types of\n"
          "  tests/interop/ros2_types.idl (Cyclone DDS) and prints a JSON report on stdout.\n"
          "  --allow-time-resets  header stamps may go back (a run reset to sim time 0)\n"
          "  Exit status: 0 all messages decode and are sane, 1 a check failed, 2 usage error.\n");
}

int main(int argc, char **argv) {
  bag_t bag;
  memset(&bag, 0, sizeof bag);
  const char *dir = NULL;
  for (int i = 1; i < argc; ++i) {
    if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
      usage(stdout);
      return 0;
    } else if (strcmp(argv[i], "--allow-time-resets") == 0) {
      bag.allow_time_resets = true;
    } else if (argv[i][0] == '-' || dir != NULL) {
      fprintf(stderr, "hadal-bag-check: unexpected argument %s\n", argv[i]);
      usage(stderr);
      return 2;
    } else {
      dir = argv[i];
    }
  }
  if (dir == NULL) {
    usage(stderr);
    return 2;
  }
  struct stat sb;
  if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode)) {
    fprintf(stderr, "hadal-bag-check: %s: not a directory (%s)\n", dir, errno ? strerror(errno) : "a file");
    return 2;
  }

  metadata_t md;
  bool usable = read_metadata(&bag, dir, &md);
  if (usable && !md.present) {
    fprintf(stderr, "hadal-bag-check: warning: %s has no metadata.yaml; reading every *.db3 in it\n", dir);
    list_databases(dir, &md);
    if (md.n_files == 0) fail(&bag, NULL, -1, "%s: no metadata.yaml and no *.db3 database", dir);
  }
  long long total = 0;
  for (size_t i = 0; usable && i < md.n_files; ++i) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, md.files[i]);
    if (stat(path, &sb) != 0) {
      /* Older rosbag2 versions listed the files with the bag directory's name in front. */
      const char *base = strrchr(md.files[i], '/');
      if (base != NULL) snprintf(path, sizeof path, "%s/%s", dir, base + 1);
    }
    if (stat(path, &sb) != 0 || !S_ISREG(sb.st_mode)) {
      fail(&bag, NULL, -1, "%s: database %s (metadata.yaml, relative_file_paths) does not exist", dir, md.files[i]);
      continue;
    }
    check_database(&bag, path, md.files[i], &total);
  }

  /* metadata.yaml against the databases: the same topics, types and counts. */
  long long decoded = 0;
  for (size_t i = 0; i < bag.n_topics; ++i) {
    topic_t *t = &bag.topics[i];
    decoded += t->decoded;
    if (!md.present) continue;
    if (t->type == NULL) {
      fail(&bag, t, -1, "topic \"%s\" (type \"%s\", %ld messages): in metadata.yaml, in no database's topics table",
           t->name, t->metadata_type ? t->metadata_type : "", t->metadata_count);
    } else if (t->metadata_count < 0) {
      fail(&bag, t, -1, "%s: in the database but not in metadata.yaml", t->name);
    } else {
      if (t->metadata_count != t->count)
        fail(&bag, t, -1, "%s: metadata.yaml says %ld messages, the database has %ld", t->name, t->metadata_count,
             t->count);
      if (t->metadata_type != NULL && strcmp(t->metadata_type, t->type) != 0)
        fail(&bag, t, -1, "%s: metadata.yaml says type %s, the database %s", t->name, t->metadata_type, t->type);
    }
  }
  if (md.present && md.message_count >= 0 && md.message_count != total)
    fail(&bag, NULL, -1, "metadata.yaml says %lld messages in all, the databases hold %lld", md.message_count, total);

  print_json(&bag, dir, &md, total, decoded);
  const int status = bag.total_errors == 0 ? 0 : 1;
  for (size_t i = 0; i < bag.n_topics; ++i) {
    topic_t *t = &bag.topics[i];
    free(t->name);
    free(t->type);
    free(t->format);
    free(t->metadata_type);
    free(t->frame_id);
  }
  free(bag.topics);
  for (size_t i = 0; i < bag.n_errors; ++i) free(bag.errors[i]);
  free(bag.errors);
  for (size_t i = 0; i < md.n_files; ++i) free(md.files[i]);
  free(md.files);
  free(md.compression_format);
  return status;
}
