/* keel-bench-dds-raw: the plain CycloneDDS C program `keel bench dds` measures keel beside. It
 * does what keel's components do in the same benchmark, with the same message (ROS 2's
 * std_msgs/msg/Header, idlc's C type of it), the same topics and the same QoS as keel's
 * `qos="default"` (reliable, keep last 10, volatile), and nothing of keel:
 *
 *   keel-bench-dds-raw pong TOPIC_IN TOPIC_OUT
 *       takes every sample of TOPIC_IN and writes it back on TOPIC_OUT, as it came (a WaitSet
 *       thread: woken per sample, as keel's aperiodic echo is)
 *   keel-bench-dds-raw ping TOPIC_OUT TOPIC_IN N PERIOD_US
 *       once both ends are matched, writes N + 100 stamps (sec/nanosec: CLOCK_MONOTONIC right
 *       before the write) every PERIOD_US; a WaitSet thread takes the echoes and keeps
 *       arrival − stamp; prints `rtt <ns>` for each of the last N (the first 100 warm up), then
 *       `done`
 *   keel-bench-dds-raw writer TOPIC PERIOD_US DEADLINE_MS
 *       writes a stamp every PERIOD_US forever, offering a deadline of DEADLINE_MS; prints
 *       `matched` once a reader is (the peer a keel subscriber watches)
 *
 * The domain is ROS_DOMAIN_ID's (0 without it); CycloneDDS's configuration is CYCLONEDDS_URI's,
 * as for keel. Exits 2 on a usage error, 1 when DDS refuses something (the reason on stderr). */
#include <errno.h>
#include <inttypes.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "dds/dds.h"
#include "std_msgs/msg/Header_.h"

#define WARM_UP 100

static int64_t monotonic_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static void sleep_until(int64_t t_ns) {
  struct timespec ts = {.tv_sec = t_ns / 1000000000, .tv_nsec = t_ns % 1000000000};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR) {}
}

static dds_entity_t check(dds_entity_t e, const char* what) {
  if (e < 0) {
    fprintf(stderr, "keel-bench-dds-raw: %s: %s\n", what, dds_strretcode(e));
    exit(1);
  }
  return e;
}

static dds_entity_t participant(void) {
  const char* env = getenv("ROS_DOMAIN_ID");
  const dds_domainid_t domain = env && *env ? (dds_domainid_t)strtoul(env, NULL, 10) : 0;
  return check(dds_create_participant(domain, NULL, NULL), "participant");
}

/* keel's qos="default": reliable (100 ms blocking), keep last 10, volatile; a deadline offered
 * when deadline_ms > 0. */
static dds_qos_t* default_qos(int deadline_ms) {
  dds_qos_t* q = dds_create_qos();
  dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
  dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 10);
  if (deadline_ms > 0) dds_qset_deadline(q, DDS_MSECS(deadline_ms));
  return q;
}

static dds_entity_t endpoint(dds_entity_t pp, const char* topic_name, int writer, int deadline_ms) {
  const dds_entity_t topic = check(dds_create_topic(pp, &std_msgs_msg_dds__Header__desc, topic_name, NULL, NULL),
                                   topic_name);
  dds_qos_t* q = default_qos(deadline_ms);
  const dds_entity_t e = writer ? dds_create_writer(pp, topic, q, NULL) : dds_create_reader(pp, topic, q, NULL);
  dds_delete_qos(q);
  return check(e, writer ? "writer" : "reader");
}

static void stamp(std_msgs_msg_dds__Header_* h) {
  const int64_t now = monotonic_ns();
  h->stamp.sec = (int32_t)(now / 1000000000);
  h->stamp.nanosec = (uint32_t)(now % 1000000000);
}

/* A WaitSet on `reader`'s data: returns once a sample may be taken, 0; or <0 at `until`. */
static int wait_data(dds_entity_t waitset, dds_time_t until) {
  dds_attach_t hit;
  return (int)dds_waitset_wait_until(waitset, &hit, 1, until) > 0 ? 0 : -1;
}

static dds_entity_t waitset_on(dds_entity_t pp, dds_entity_t reader) {
  const dds_entity_t ws = check(dds_create_waitset(pp), "waitset");
  const dds_entity_t cond = check(dds_create_readcondition(reader, DDS_ANY_STATE), "read condition");
  check(dds_waitset_attach(ws, cond, reader), "attach");
  return ws;
}

static int pong(const char* in, const char* out) {
  const dds_entity_t pp = participant();
  const dds_entity_t reader = endpoint(pp, in, 0, 0);
  const dds_entity_t writer = endpoint(pp, out, 1, 0);
  const dds_entity_t ws = waitset_on(pp, reader);
  for (;;) {
    if (wait_data(ws, DDS_NEVER) != 0) continue;
    void* samples[1] = {NULL};
    dds_sample_info_t info[1];
    while (dds_take(reader, samples, info, 1, 1) > 0) {
      if (info[0].valid_data) dds_write(writer, samples[0]);
      dds_return_loan(reader, samples, 1);
      samples[0] = NULL;
    }
  }
  return 0;
}

struct ping_state {
  dds_entity_t reader, waitset;
  int expected; /* echoes to wait for: N + WARM_UP */
  int64_t* rtt;
  volatile int received;
};

static void* ping_reader(void* arg) {
  struct ping_state* s = arg;
  const dds_time_t until = dds_time() + DDS_SECS(60);
  while (s->received < s->expected && dds_time() < until) {
    if (wait_data(s->waitset, until) != 0) break;
    const int64_t now = monotonic_ns();
    void* samples[1] = {NULL};
    dds_sample_info_t info[1];
    while (dds_take(s->reader, samples, info, 1, 1) > 0) {
      const std_msgs_msg_dds__Header_* h = samples[0];
      if (info[0].valid_data && s->received < s->expected)
        s->rtt[s->received++] = now - ((int64_t)h->stamp.sec * 1000000000 + h->stamp.nanosec);
      dds_return_loan(s->reader, samples, 1);
      samples[0] = NULL;
    }
  }
  return NULL;
}

/* Both ends matched (a publication and a subscription), or <0 at the bound. */
static int await_match(dds_entity_t writer, dds_entity_t reader, int64_t bound_ns) {
  const int64_t until = monotonic_ns() + bound_ns;
  while (monotonic_ns() < until) {
    dds_publication_matched_status_t pub;
    dds_subscription_matched_status_t sub;
    if (dds_get_publication_matched_status(writer, &pub) == 0 && pub.current_count > 0 &&
        (reader == 0 || (dds_get_subscription_matched_status(reader, &sub) == 0 && sub.current_count > 0)))
      return 0;
    dds_sleepfor(DDS_MSECS(1));
  }
  return -1;
}

static int ping(const char* out, const char* in, int n, int period_us) {
  const dds_entity_t pp = participant();
  const dds_entity_t writer = endpoint(pp, out, 1, 0);
  struct ping_state s = {.reader = endpoint(pp, in, 0, 0), .expected = n + WARM_UP};
  s.waitset = waitset_on(pp, s.reader);
  s.rtt = calloc((size_t)s.expected, sizeof *s.rtt);
  if (await_match(writer, s.reader, 20000000000LL) != 0) {
    fprintf(stderr, "keel-bench-dds-raw: ping: no pong matched within 20 s\n");
    return 1;
  }
  dds_sleepfor(DDS_MSECS(100)); /* the pong's own ends matched too */
  pthread_t thread;
  pthread_create(&thread, NULL, ping_reader, &s);
  std_msgs_msg_dds__Header_ h = {.frame_id = "0"};
  int64_t next = monotonic_ns();
  for (int i = 0; i < s.expected; ++i) {
    next += (int64_t)period_us * 1000;
    sleep_until(next);
    stamp(&h);
    dds_write(writer, &h);
  }
  pthread_join(thread, NULL);
  for (int i = WARM_UP; i < s.received; ++i) printf("rtt %" PRId64 "\n", s.rtt[i]);
  printf("done\n");
  free(s.rtt);
  return 0;
}

static int writer(const char* topic, int period_us, int deadline_ms) {
  const dds_entity_t pp = participant();
  const dds_entity_t w = endpoint(pp, topic, 1, deadline_ms);
  if (await_match(w, 0, 20000000000LL) != 0) {
    fprintf(stderr, "keel-bench-dds-raw: writer: no reader matched within 20 s\n");
    return 1;
  }
  printf("matched\n");
  fflush(stdout);
  std_msgs_msg_dds__Header_ h = {.frame_id = "1"};
  int64_t next = monotonic_ns();
  for (;;) {
    next += (int64_t)period_us * 1000;
    sleep_until(next);
    stamp(&h);
    dds_write(w, &h);
  }
}

int main(int argc, char** argv) {
  if (argc == 4 && strcmp(argv[1], "pong") == 0) return pong(argv[2], argv[3]);
  if (argc == 6 && strcmp(argv[1], "ping") == 0) return ping(argv[2], argv[3], atoi(argv[4]), atoi(argv[5]));
  if (argc == 5 && strcmp(argv[1], "writer") == 0) return writer(argv[2], atoi(argv[3]), atoi(argv[4]));
  fprintf(stderr,
          "usage: keel-bench-dds-raw pong TOPIC_IN TOPIC_OUT\n"
          "       keel-bench-dds-raw ping TOPIC_OUT TOPIC_IN N PERIOD_US\n"
          "       keel-bench-dds-raw writer TOPIC PERIOD_US DEADLINE_MS\n");
  return 2;
}
