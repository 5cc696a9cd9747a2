#!/usr/bin/env node
// A stand-in for `keel run APP.xml --monitor [ADDR:]PORT`, for developing and testing the monitor's
// page (src/monitor/page/index.html) without keel: Foxglove's own server class
// (@foxglove/ws-protocol's FoxgloveServer) on `ws`'s WebSocketServer, plus node's http serving the
// page on `/`, all on one port as keel does. It plays a scripted run: four components in two
// applications, the fault-log records of a fault every --fault-every ms (a crash reset, a hang
// caught by the watchdog, an out-of-range value ignored, an exception escalated to a
// replacement), a server status message, port values while subscribed, and the emergency
// services, which want the token it prints:
//
//   monitor: http://127.0.0.1:PORT/?token=TOKEN
//
// Usage: node tests/monitor/mock_server.mjs [--monitor [ADDR:]PORT] [--fault-every MS]
//                                           [--duration S] [--token HEX]
// Modules come from tests/peers/node_modules (scripts/peers.sh installs them): resolved with
// createRequire from tests/peers/package.json, so neither NODE_PATH nor the working directory
// matters.
import { createRequire } from "node:module";
import { randomBytes } from "node:crypto";
import { readFileSync } from "node:fs";
import http from "node:http";

const require = createRequire(new URL("../peers/package.json", import.meta.url));
const { FoxgloveServer } = require("@foxglove/ws-protocol");
const { WebSocketServer } = require("ws");

// KEEL_MONITOR_PAGE: another page to serve (a broken copy, to see the page's test fail).
const PAGE = process.env.KEEL_MONITOR_PAGE || new URL("../../src/monitor/page/index.html", import.meta.url);

function parseArgs(argv) {
  const o = { addr: "127.0.0.1", port: 0, faultEvery: 2500, duration: 0, token: randomBytes(16).toString("hex") };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i], v = argv[i + 1];
    if (a === "--monitor") {
      const m = /^(?:(.*):)?(\d+)$/.exec(v || "");
      if (!m) throw new Error(`--monitor wants [ADDR:]PORT, not '${v}'`);
      if (m[1]) o.addr = m[1];
      o.port = Number(m[2]);
      i++;
    } else if (a === "--fault-every") { o.faultEvery = Number(v); i++; }
    else if (a === "--duration") { o.duration = Number(v); i++; }
    else if (a === "--token") { o.token = v; i++; }
    else throw new Error(`unknown option '${a}'`);
  }
  return o;
}
const opts = parseArgs(process.argv.slice(2));

// ------------------------------------------------------------------ the run
const start = process.hrtime.bigint();
const startUnixNs = BigInt(Date.now()) * 1000000n;
const tNs = () => Number(process.hrtime.bigint() - start);
const unixNs = () => startUnixNs + BigInt(tNs());

const run = {
  name: "mock_rover",
  emergency: false,
  components: [
    { name: "nav.sonar", application: "nav", state: "Created", faults: 0 },
    { name: "nav.planner", application: "nav", state: "Created", faults: 0 },
    { name: "base.driver", application: "base", state: "Created", faults: 0, pid: 4242 },
    { name: "base.battery", application: "base", state: "Created", faults: 0 },
  ],
  connections: [
    { from: "nav.sonar", from_port: "distance", to: "nav.planner", to_port: "range" },
    { from: "base.battery", from_port: "voltage", to: "nav.planner", to_port: "battery" },
    { from: "nav.planner", from_port: "cmd", to: "base.driver", to_port: "cmd" },
    { from: "base.driver", from_port: "odom", to: "nav.planner", to_port: "odom" },
  ],
};
const comp = (name) => run.components.find((c) => c.name === name);

const schema = (properties) => JSON.stringify({ type: "object", properties, additionalProperties: true });
const server = new FoxgloveServer({
  name: "keel",
  capabilities: ["services"],
  supportedEncodings: ["json"],
  metadata: { run: run.name, profile: "tests/monitor/mock_server.mjs", start_unix_ns: String(startUnixNs) },
  sessionId: `${process.pid}-${startUnixNs}`,
});
const stateCh = server.addChannel({
  topic: "/keel/state", encoding: "json", schemaName: "keel.State", schemaEncoding: "jsonschema",
  schema: schema({ t_ns: { type: "integer" }, run: { type: "string" }, emergency: { type: "boolean" },
    components: { type: "array" }, connections: { type: "array" } }),
});
const faultCh = server.addChannel({
  topic: "/keel/faults", encoding: "json", schemaName: "keel.FaultRecord", schemaEncoding: "jsonschema",
  schema: schema({ event: { type: "string" }, t_ns: { type: "integer" }, fault_id: { type: "integer" }, component: { type: "string" } }),
});
const ports = new Map();  // channel id -> {component, port, sample()}
function addPort(component, port, sample) {
  const id = server.addChannel({
    topic: `/keel/ports/${component}/${port}`, encoding: "json", schemaName: "keel.PortValue",
    schemaEncoding: "jsonschema", schema: schema({ t_ns: { type: "integer" }, value: {} }),
  });
  ports.set(id, { component, port, sample, subscribed: false });
}
addPort("nav.sonar", "distance", (t) => Math.round((1.5 + Math.sin(t / 7e8)) * 1000) / 1000);
addPort("nav.planner", "cmd", (t) => ({ v: Math.round(50 * Math.cos(t / 9e8)) / 100, w: Math.round(30 * Math.sin(t / 5e8)) / 100 }));
addPort("base.driver", "odom", (t) => ({ x: Math.round(t / 1e7) / 100, y: 0, heading_deg: Math.round(t / 1e8) % 360 }));
addPort("base.battery", "voltage", (t) => Math.round((24.6 - t / 1e11) * 100) / 100);
addPort("base.battery", "low", () => false);

const encoder = new TextEncoder();
const publish = (channel, payload) => server.sendMessage(channel, unixNs(), encoder.encode(JSON.stringify(payload)));
const sendState = () => publish(stateCh, { t_ns: tNs(), run: run.name, emergency: run.emergency, components: run.components, connections: run.connections });

function record(fields) {
  const r = { t_ns: tNs(), ...fields };
  if (r.event === "state" && r.component) comp(r.component).state = r.to;
  if (r.event === "detected") comp(r.component).faults += 1;
  publish(faultCh, r);
  if (r.event === "state" || r.event === "detected") sendState();
  return r;
}

server.on("subscribe", (id) => {
  if (id === stateCh) sendState();
  if (ports.has(id)) ports.get(id).subscribed = true;
});
server.on("unsubscribe", (id) => { if (ports.has(id)) ports.get(id).subscribed = false; });
server.on("error", (e) => console.error("mock: server error:", e.message));

// ------------------------------------------------------------------ the script
const timers = [];
const at = (ms, fn) => timers.push(setTimeout(fn, ms));
const every = (ms, fn) => timers.push(setInterval(fn, ms));

record({ event: "engine", phase: "load", profile: "mock_rover.xml", name: run.name, instances: run.components.length, components: run.components.map((c) => c.name) });
at(60, () => { for (const c of run.components) record({ event: "state", component: c.name, from: "Created", to: "Ready" }); });
at(120, () => {
  record({ event: "engine", phase: "started", executors: 2 });
  for (const c of run.components) record({ event: "state", component: c.name, from: "Ready", to: "Active" });
});
every(250, sendState);  // keel: at least once a second; faster here so tests wait less
every(50, () => { for (const [id, p] of ports) if (p.subscribed) publish(id, { t_ns: tNs(), value: p.sample(tNs()) }); });
at(3000, () => server.sendStatus({ level: 1, message: "12 messages dropped: client too slow", id: "drops" }));

let nextFault = 1;
// Each fault is a list of [delay ms after the previous record, record fields]; fault_id and
// component are added.
const FAULTS = [
  ["nav.sonar", [
    [0, { event: "armed", kind: "segfault" }],
    [15, { event: "injected" }],
    [0.2, { event: "detected", kind: "signal", detector: "nav.sonar", detail: "SIGSEGV: invalid read at address 0x0 in Sonar::onExecute" }],
    [0, { event: "state", from: "Active", to: "Error" }],
    [0.05, { event: "diagnosed", severity: "reset", rules: "fault_policy", scope: "component", handling: "reset" }],
    [0.3, { event: "action", action: "reset", outcome: "ok", detail: "onError → onReset → onRecover" }],
    [0, { event: "state", from: "Error", to: "Active" }],
    [0.4, { event: "recovered" }],
  ]],
  ["nav.planner", [
    [0, { event: "armed", kind: "hang" }],
    [20, { event: "injected" }],
    [100, { event: "detected", kind: "heartbeat", detector: "watchdog", detail: "a callback has not returned for 100.070 ms (heartbeat timeout 100.000 ms)" }],
    [0, { event: "state", from: "Active", to: "Error" }],
    [0.03, { event: "diagnosed", severity: "reset", rules: "fault_policy", scope: "component", handling: "reset" }],
    [0.25, { event: "action", action: "reset", outcome: "ok", detail: "onError → onReset → onRecover" }],
    [0, { event: "state", from: "Error", to: "Active" }],
    [0.1, { event: "recovered" }],
  ]],
  ["base.battery", [
    [0, { event: "armed", kind: "out_of_range" }],
    [10, { event: "injected" }],
    [0.01, { event: "detected", kind: "out_of_range", detector: "base.battery", detail: "port voltage: 0 outside [18, 30]" }],
    [0.02, { event: "diagnosed", severity: "ignore", rules: "fault_policy", scope: "component", handling: "ignore" }],
    [0.01, { event: "action", action: "ignore", outcome: "ok" }],
  ]],
  ["base.driver", [
    [0, { event: "armed", kind: "throw" }],
    [5, { event: "injected" }],
    [0.05, { event: "detected", kind: "exception", detector: "base.driver", detail: "std::runtime_error: motor controller did not answer" }],
    [0, { event: "state", from: "Active", to: "Error" }],
    [0.04, { event: "diagnosed", severity: "reset", rules: "fault_policy", scope: "component", handling: "reset" }],
    [0.8, { event: "action", action: "reset", outcome: "failed", detail: "onReset returned error_code" }],
    [0.02, { event: "action", action: "escalate", outcome: "ok", detail: "reset → replace: the reset failed" }],
    [2.5, { event: "action", action: "replace", outcome: "ok", replacement: "SafeDriver" }],
    [0, { event: "state", from: "Ready", to: "Active" }],
    [1.2, { event: "recovered" }],
  ]],
];
let faultIndex = 0;
function injectNext() {
  const [component, steps] = FAULTS[faultIndex++ % FAULTS.length];
  const fault_id = nextFault++;
  let delay = 0, detectedT = null;
  for (const [ms, fields] of steps) {
    delay += ms;
    at(delay, () => {
      const r = { ...fields, fault_id, component };
      if (r.event === "recovered") r.latency_us = Math.round((tNs() - detectedT) / 1000 * 1000) / 1000;
      const written = record(r);
      if (r.event === "detected") detectedT = written.t_ns;
    });
  }
}
at(1200, () => { injectNext(); every(opts.faultEvery, injectNext); });

// ------------------------------------------------------------------ services
const services = {
  emergency_stop: server.addService({
    name: "/keel/emergency_stop", type: "keel/Control",
    request: { encoding: "json", schemaName: "keel.ControlRequest", schemaEncoding: "jsonschema", schema: schema({ token: { type: "string" } }) },
    response: { encoding: "json", schemaName: "keel.ControlResponse", schemaEncoding: "jsonschema", schema: schema({ ok: { type: "boolean" }, detail: { type: "string" } }) },
  }),
};
services.clear_emergency = server.addService({
  name: "/keel/clear_emergency", type: "keel/Control",
  request: { encoding: "json", schemaName: "keel.ControlRequest", schemaEncoding: "jsonschema", schema: schema({ token: { type: "string" } }) },
  response: { encoding: "json", schemaName: "keel.ControlResponse", schemaEncoding: "jsonschema", schema: schema({ ok: { type: "boolean" }, detail: { type: "string" } }) },
});
const decoder = new TextDecoder();
server.on("serviceCallRequest", (req, connection) => {
  const fail = (message) => server.sendServiceCallFailure({ op: "serviceCallFailure", serviceId: req.serviceId, callId: req.callId, message }, connection);
  let body;
  try {
    body = JSON.parse(decoder.decode(req.data));
  } catch {
    return fail("bad request: not JSON");
  }
  if (typeof body.token !== "string" || body.token === "") return fail("token required");
  if (body.token !== opts.token) return fail("bad token");
  const ok = (detail) => server.sendServiceCallResponse(
    { serviceId: req.serviceId, callId: req.callId, encoding: "json", data: encoder.encode(JSON.stringify({ ok: true, detail })) }, connection);
  if (req.serviceId === services.emergency_stop) {
    const names = run.components.map((c) => c.name);
    record({ event: "action", action: "emergency_stop", outcome: "ok", by: "monitor", components: names, latency_us: 842.5, detail: "onEmergencyStop ran" });
    run.emergency = true;
    record({ event: "emergency", phase: "latched", by: "monitor" });
    sendState();
    ok(`latched; onEmergencyStop ran in ${names.length} components`);
  } else if (req.serviceId === services.clear_emergency) {
    const was = run.emergency;
    record({ event: "action", action: "clear", outcome: "ok", by: "monitor", detail: was ? "emergency cleared" : "not latched" });
    run.emergency = false;
    if (was) record({ event: "emergency", phase: "cleared", by: "monitor" });
    sendState();
    ok(was ? "cleared" : "was not latched");
  } else {
    fail("unknown service");
  }
});

// ------------------------------------------------------------------ http + websocket, one port
const httpServer = http.createServer((req, res) => {
  const url = new URL(req.url, "http://x");
  if (req.method === "GET" && url.pathname === "/") {
    // Read at every request: edit the page, reload the browser.
    const page = readFileSync(PAGE);
    res.writeHead(200, {
      "Content-Type": "text/html; charset=utf-8", "Cache-Control": "no-store", "Referrer-Policy": "no-referrer",
      "X-Content-Type-Options": "nosniff", "Content-Length": page.length,
    });
    res.end(page);
  } else {
    res.writeHead(404, { "Content-Type": "text/plain" });
    res.end("not found\n");
  }
});
const wss = new WebSocketServer({ server: httpServer, handleProtocols: (protocols) => server.handleProtocols(protocols) });
wss.on("connection", (conn, req) => server.handleConnection(conn, `${req.socket.remoteAddress}:${req.socket.remotePort}`));

httpServer.listen(opts.port, opts.addr, () => {
  const { port } = httpServer.address();
  const host = opts.addr.includes(":") ? `[${opts.addr}]` : opts.addr;
  console.log(`monitor: http://${host}:${port}/?token=${opts.token}`);
});

function stop() {
  for (const t of timers) { clearTimeout(t); clearInterval(t); }
  for (const c of wss.clients) c.terminate();
  wss.close();
  httpServer.close(() => process.exit(0));
  setTimeout(() => process.exit(0), 500).unref();
}
process.on("SIGTERM", stop);
process.on("SIGINT", stop);
if (opts.duration > 0) setTimeout(stop, opts.duration * 1000);
