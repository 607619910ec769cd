/* What the Cyclone DDS probes that act as a ROS 2 node share (ros2_lockstep_probe.c, ros2_joint_probe.c):
 * their "ok:"/"FAIL:" checks, loopback-only discovery, reliable volatile endpoints and waiting for a match.
 * Header-only (static functions): each probe is one C file. */
#ifndef HADAL_INTEROP_PROBE_COMMON_H
#define HADAL_INTEROP_PROBE_COMMON_H

#include <dds/dds.h>

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "ros2_types.h"

static int failures = 0;

static void check(bool ok, const char *what, double a, double b) {
  printf("%s: %s (%.6g, %.6g)\n", ok ? "ok" : "FAIL", what, a, b);
  if (!ok) ++failures;
}

static void configure_loopback(void) {
  const char *uri = getenv("CYCLONEDDS_URI");
  if (uri != NULL && *uri != '\0') return;
  setenv("CYCLONEDDS_URI",
         "<CycloneDDS><Domain id=\"any\"><General><Interfaces><NetworkInterface address=\"127.0.0.1\"/>"
         "</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery>"
         "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>31</MaxAutoParticipantIndex>"
         "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery></Domain></CycloneDDS>",
         1);
}

static dds_entity_t endpoint(dds_entity_t pp, const dds_topic_descriptor_t *desc, const char *name, bool writer) {
  dds_entity_t topic = dds_create_topic(pp, desc, name, NULL, NULL);
  if (topic < 0) return topic;
  dds_qos_t *qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 32);
  dds_entity_t e = writer ? dds_create_writer(pp, topic, qos, NULL) : dds_create_reader(pp, topic, qos, NULL);
  dds_delete_qos(qos);
  return e;
}

static bool wait_matched(dds_entity_t writer, double seconds) {
  for (int i = 0; i < (int)(seconds * 100); ++i) {
    dds_publication_matched_status_t status;
    if (dds_get_publication_matched_status(writer, &status) == DDS_RETCODE_OK && status.current_count > 0)
      return true;
    dds_sleepfor(DDS_MSECS(10));
  }
  return false;
}

/* Takes step replies until the one for `id` arrives (or 20 s pass), handing it to `take` with `ctx` while the
   reader's loan lasts (its sequences are not kept: `take` copies what it needs). */
typedef void (*reply_taker)(const hadal_msgs_msg_dds__StepReply_ *reply, void *ctx);
static bool await_step_reply(dds_entity_t reader, uint64_t id, reply_taker take, void *ctx) {
  for (int i = 0; i < 20000; ++i) {
    void *samples[1] = {NULL};
    dds_sample_info_t info;
    while (dds_take(reader, samples, &info, 1, 1) > 0) {
      const hadal_msgs_msg_dds__StepReply_ *r = samples[0];
      const bool mine = info.valid_data && r->request_id == id;
      if (mine) take(r, ctx);
      dds_return_loan(reader, samples, 1);
      samples[0] = NULL;
      if (mine) return true;
    }
    dds_sleepfor(DDS_MSECS(1));
  }
  return false;
}

/* Waits up to `seconds` until both readers are matched by a writer (hadald's writers may lag its readers);
   true once they are. */
static bool wait_subscribed(dds_entity_t reader_a, dds_entity_t reader_b, double seconds) {
  for (int i = 0; i < (int)(seconds * 100); ++i) {
    dds_subscription_matched_status_t a, b;
    dds_get_subscription_matched_status(reader_a, &a);
    dds_get_subscription_matched_status(reader_b, &b);
    if (a.current_count > 0 && b.current_count > 0) return true;
    dds_sleepfor(DDS_MSECS(10));
  }
  return false;
}

#endif
