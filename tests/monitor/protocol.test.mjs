// The monitor's protocol, checked with Foxglove's own client library (@foxglove/ws-protocol
// from npm) against `keel run --monitor` running examples/02 with its faults injected: what
// Foxglove's app would see. Run: node --test tests/monitor/protocol.test.mjs (KEEL_CLI: the
// keel to test).
import assert from "node:assert/strict";
import net from "node:net";
import { after, before, test } from "node:test";

import { peers, startKeel, stopKeel, testComponents, until } from "./run_keel.mjs";

const { FoxgloveClient } = peers("@foxglove/ws-protocol");
const WebSocket = peers("ws");

const app = "examples/02_fault_detection";
let run;

before(async () => {
  run = await startKeel([`${app}/app.xml`, "--inject", `${app}/scenario.xml`, "--duration", "60"]);
});
after(async () => {
  const code = await stopKeel(run);
  assert.equal(code, 0, `keel run ended badly:\n${run.output()}`);
});

/** A Foxglove client subscribed to every channel, keeping what it receives. */
function connect(options = {}) {
  const ws = new WebSocket(`ws://${run.host}/`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL], options);
  const client = new FoxgloveClient({ ws });
  const seen = { info: undefined, channels: [], services: [], topics: new Map(), messages: [], failures: [], responses: [], statuses: [], closed: false };
  const decoder = new TextDecoder();
  // Every handler before the first await: one TCP read may carry serverInfo, advertise and more.
  client.on("serverInfo", (info) => (seen.info = info));
  client.on("advertise", (channels) => {
    for (const c of channels) {
      seen.channels.push(c);
      seen.topics.set(client.subscribe(c.id), c.topic);
    }
  });
  client.on("advertiseServices", (services) => seen.services.push(...services));
  client.on("message", ({ subscriptionId, timestamp, data }) =>
    seen.messages.push({ topic: seen.topics.get(subscriptionId), timestamp, body: JSON.parse(decoder.decode(data)) }),
  );
  client.on("serviceCallFailure", (f) => seen.failures.push(f));
  client.on("serviceCallResponse", (r) => seen.responses.push({ ...r, body: JSON.parse(decoder.decode(r.data)) }));
  client.on("status", (s) => seen.statuses.push(s));
  client.on("close", () => (seen.closed = true));
  client.on("error", () => {});
  return { client, ws, seen };
}

const on = (seen, topic) => seen.messages.filter((m) => m.topic === topic).map((m) => m.body);
const service = (seen, name) => seen.services.find((s) => s.name === name);
function call(client, seen, name, request, callId) {
  client.sendServiceCallRequest({
    serviceId: service(seen, name).id,
    callId,
    encoding: "json",
    data: new DataView(new TextEncoder().encode(JSON.stringify(request)).buffer),
  });
}
const reply = (seen, callId) =>
  seen.responses.find((r) => r.callId === callId) ?? seen.failures.find((f) => f.callId === callId);

test("serverInfo, channels with JSON schemas, and the control services are announced", async () => {
  const { client, seen } = connect();
  await until(() => (seen.info && seen.channels.length >= 2 && seen.services.length >= 2 ? true : undefined), "announcements");
  assert.deepEqual(seen.info.capabilities, ["services"]);
  assert.deepEqual(seen.info.supportedEncodings, ["json"]);
  assert.equal(seen.info.metadata.run, "fault_detection");
  assert.match(seen.info.metadata.start_unix_ns, /^\d+$/);
  for (const topic of ["/keel/state", "/keel/faults"]) {
    const c = seen.channels.find((ch) => ch.topic === topic);
    assert.ok(c, `${topic} advertised`);
    assert.equal(c.encoding, "json");
    assert.equal(c.schemaEncoding, "jsonschema");
    assert.equal(JSON.parse(c.schema).type, "object");
  }
  assert.ok(service(seen, "/keel/emergency_stop"));
  assert.ok(service(seen, "/keel/clear_emergency"));
  client.close();
});

test("the state names every component; a crash arrives on /keel/faults with its handling", async () => {
  const { client, seen } = connect();
  const state = await until(() => on(seen, "/keel/state").at(-1), "a state snapshot");
  assert.deepEqual(state.components.map((c) => c.name).sort(), ["avoider", "sonar_left", "sonar_right"]);
  assert.equal(state.connections.length, 2);
  // sonar_left segfaults on its 25th cycle (0.5 s in); a client connected later gets the records so far.
  const detected = await until(
    () => on(seen, "/keel/faults").find((r) => r.event === "detected" && r.component === "sonar_left"),
    "the segfault's detection",
  );
  assert.equal(detected.kind, "signal");
  // Its diagnosis follows it: another line of the log, which the monitor may send a moment later.
  await until(
    () => on(seen, "/keel/faults").find((r) => r.event === "diagnosed" && r.fault_id === detected.fault_id),
    "the segfault's diagnosis",
  );
  const later = await until(
    () => on(seen, "/keel/state").find((s) => s.components.find((c) => c.name === "sonar_left").faults >= 1),
    "the fault counted in the state",
  );
  // In Error until its reset (its default policy): a snapshot taken after the reset (a slow
  // machine, a sanitizer) shows it Active, and then the fault's recovery is on record.
  const sonarState = later.components.find((c) => c.name === "sonar_left").state;
  if (sonarState !== "Error") {
    assert.equal(sonarState, "Active");
    await until(
      () => on(seen, "/keel/faults").find((r) => r.event === "recovered" && r.fault_id === detected.fault_id),
      "the recovery of a fault whose component is Active again",
    );
  }
  // Message timestamps are Unix ns: the record's t_ns past the run's start.
  const m = seen.messages.find(
    (x) => x.topic === "/keel/faults" && x.body.event === "detected" && x.body.fault_id === detected.fault_id,
  );
  assert.equal(m.timestamp, BigInt(seen.info.metadata.start_unix_ns) + BigInt(detected.t_ns));
  client.close();
});

test("the emergency stop and clear need the token; with it they latch and clear", async () => {
  const { client, seen } = connect();
  await until(() => (seen.services.length >= 2 ? true : undefined), "services");
  call(client, seen, "/keel/emergency_stop", {}, 1);
  call(client, seen, "/keel/emergency_stop", { token: "0".repeat(32) }, 2);
  assert.match((await until(() => reply(seen, 1), "call 1")).message, /token required/);
  assert.match((await until(() => reply(seen, 2), "call 2")).message, /bad token/);
  assert.equal(on(seen, "/keel/state").at(-1)?.emergency ?? false, false, "refused calls latch nothing");

  call(client, seen, "/keel/emergency_stop", { token: run.token }, 3);
  const latched = await until(() => reply(seen, 3), "call 3");
  assert.equal(latched.body.ok, true, JSON.stringify(latched));
  await until(() => (on(seen, "/keel/state").at(-1)?.emergency === true ? true : undefined), "the latch in the state");
  assert.ok(on(seen, "/keel/faults").some((r) => r.event === "emergency" && r.phase === "latched" && r.by === "monitor"));

  call(client, seen, "/keel/clear_emergency", { token: run.token }, 4);
  assert.equal((await until(() => reply(seen, 4), "call 4")).body.ok, true);
  await until(() => (on(seen, "/keel/state").at(-1)?.emergency === false ? true : undefined), "the clear in the state");
  await until(() => on(seen, "/keel/faults").find((r) => r.event === "action" && r.action === "clear" && r.by === "monitor"), "the clear's action record");
  client.close();
});

test("a port's values come on its channel while subscribed, and stop after", async () => {
  // examples/01's talker counts on `count` (int) every period, for the whole run.
  const hello = await startKeel(["examples/01_hello_component/app.xml", "--duration", "30"]);
  try {
    const ws = new WebSocket(`ws://${hello.host}/`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
    const client = new FoxgloveClient({ ws });
    const topic = "/keel/ports/talker/count";
    const channels = [];
    const values = [];
    let sub;
    client.on("advertise", (chs) => channels.push(...chs));
    client.on("message", ({ subscriptionId, data }) => {
      if (subscriptionId === sub) values.push(JSON.parse(new TextDecoder().decode(data)));
    });
    const channel = await until(() => channels.find((c) => c.topic === topic), `${topic} advertised`);
    assert.equal(JSON.parse(channel.schema).properties.value.type, "integer");
    assert.ok(!channels.some((c) => c.topic === "/keel/ports/talker/news"), "an event without a JSON form is not offered");
    sub = client.subscribe(channel.id);
    await until(() => (values.length >= 5 ? true : undefined), "values keep coming");
    assert.ok(values.every((v) => Number.isInteger(v.value) && Number.isInteger(v.t_ns)));
    const counted = values.slice(1).map((v) => v.value); // the first is the newest kept, then live
    assert.deepEqual(counted, counted.map((_, i) => counted[0] + i), "every value, in order");
    client.unsubscribe(sub);
    await new Promise((r) => setTimeout(r, 200)); // what was on its way
    const after = values.length;
    await new Promise((r) => setTimeout(r, 500));
    assert.equal(values.length, after, "nothing after unsubscribing");
    client.close();
  } finally {
    await stopKeel(hello);
  }
});

test("a client that stops reading loses messages, is told, and slows nobody", async () => {
  // 10,000 values a second on /keel/ports/counter/count; each client may have 64 KiB queued.
  const fast = await startKeel(["tests/integration/profiles/monitor/ten_khz.xml", "--duration", "30",
                                "--monitor-queue", "64"], { env: { KEEL_COMPONENT_PATH: testComponents } });
  try {
    const watch = (name) => {
      const ws = new WebSocket(`ws://${fast.host}/`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
      const client = new FoxgloveClient({ ws });
      const got = { values: [], statuses: [], ws, client };
      let sub;
      client.on("advertise", (chs) => {
        const c = chs.find((ch) => ch.topic === "/keel/ports/counter/count");
        if (c) sub = client.subscribe(c.id);
      });
      client.on("message", ({ subscriptionId, data }) => {
        if (subscriptionId === sub) got.values.push(JSON.parse(new TextDecoder().decode(data)).value);
      });
      client.on("status", (s) => got.statuses.push(s));
      client.on("error", () => {});
      return got;
    };
    const slow = watch("slow");
    const steady = watch("steady");
    await until(() => (slow.values.length > 100 && steady.values.length > 100 ? true : undefined), "values to both");
    slow.ws._socket.pause(); // stops reading: its TCP window fills, then keel's queue for it
    const before = steady.values.length;
    await new Promise((r) => setTimeout(r, 6000));
    const during = steady.values.length - before;
    // A quarter of the rate: on a loaded 2-CPU machine the steady client got 4,500 a second; one
    // held up by the stalled client would get nothing once keel's queue for the other filled.
    assert.ok(during > 6 * 2500, `the steady client kept getting values while the other stalled: ${during} in 6 s`);
    slow.ws._socket.resume();
    const told = await until(() => slow.statuses.find((s) => /dropped/.test(s.message)), "the drop told to the slow client");
    assert.equal(told.level, 1);
    const [, count] = told.message.match(/^(\d+) messages dropped/);
    assert.ok(Number(count) > 0);
    // What the slow client got is in order with a gap, never a value twice.
    assert.ok(slow.values.every((v, i) => i === 0 || v > slow.values[i - 1]), "in order, none twice");
    const gaps = slow.values.filter((v, i) => i > 0 && v !== slow.values[i - 1] + 1).length;
    assert.ok(gaps >= 1, "values were lost where the queue was full");
    slow.client.close();
    steady.client.close();
  } finally {
    assert.equal(await stopKeel(fast), 0, "keel run ended cleanly");
  }
});

test("a page from another origin is refused; no Origin (not a browser) is accepted", async () => {
  const foreign = new WebSocket(`ws://${run.host}/`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL], { origin: "http://evil.test" });
  const refused = await new Promise((resolve) => {
    foreign.on("unexpected-response", (_req, res) => resolve(res.statusCode));
    foreign.on("open", () => resolve("opened"));
    foreign.on("error", () => {});
  });
  assert.equal(refused, 403);
  const own = new WebSocket(`ws://${run.host}/`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL], { origin: `http://${run.host}` });
  assert.equal(await new Promise((r) => (own.on("open", () => r("opened")), own.on("error", (e) => r(e.message)))), "opened");
  own.close();
});

test("another subprotocol is refused with 400", async () => {
  const ws = new WebSocket(`ws://${run.host}/`, ["something.else"]);
  const status = await new Promise((resolve) => {
    ws.on("unexpected-response", (_req, res) => resolve(res.statusCode));
    ws.on("open", () => resolve("opened"));
    ws.on("error", () => {});
  });
  assert.equal(status, 400);
});

test("bad and oversized client messages are answered or closed, and keel keeps serving", async () => {
  const { ws, seen } = connect();
  await until(() => (seen.info ? true : undefined), "serverInfo");
  ws.send("not json at all");
  ws.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: "x", channelId: 1 }] }));
  ws.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: 900, channelId: 99 }] }));
  ws.send(Buffer.from([0x02, 1, 0, 0]));
  ws.send(Buffer.from([0x7f]));
  await until(() => (seen.statuses.length >= 5 ? true : undefined), "five statuses");
  assert.deepEqual(
    seen.statuses.map((s) => s.level),
    [2, 2, 1, 2, 2],
  );
  assert.match(seen.statuses[0].message, /not JSON/);
  ws.send("x".repeat(1 << 20)); // 1 MiB: beyond the 64 KiB keel reads
  await until(() => (seen.closed ? true : undefined), "the close of an oversized message");

  // A raw socket that sends half a handshake and stalls, and one that sends garbage.
  const stall = net.connect(run.port, "127.0.0.1", () => stall.write("GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n"));
  const garbage = net.connect(run.port, "127.0.0.1", () => garbage.write(Buffer.alloc(4096, 0xff)));
  garbage.on("error", () => {});
  stall.on("error", () => {});

  const fresh = connect();
  await until(() => on(fresh.seen, "/keel/state").at(-1), "a state for a new client after all that");
  fresh.client.close();
  stall.destroy();
  garbage.destroy();
});
