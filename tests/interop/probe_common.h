/* What the Cyclone DDS probes that act as a ROS 2 node share (ros2_lockstep_probe.c, ros2_joint_probe.c):
 * their "ok:"/"FAIL:" checks, loopback-only discovery, reliable volatile endpoints and waiting for a match.
 * Header-only (static functions): each probe is one C file. */
#ifndef HADAL_INTEROP_PROBE_COMMON_H
#define HADAL_INTEROP_PROBE_COMMON_H

#include <dds/dds.h>

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>

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

#endif
