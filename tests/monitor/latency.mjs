// How soon a fault reaches a connected Foxglove client: for every `detected` record, the
// client's receive time minus the record's own time (wall clock: start_unix_ns + t_ns), while
// a counter is made to throw every 20 ms and is reset each time
// (tests/integration/profiles/monitor/faulty.xml). Prints p50/p99/max in µs (docs/performance.md).
//   node tests/monitor/latency.mjs [FAULTS]     (default 500; KEEL_CLI: the keel to measure,
//                                                KEEL_COMPONENT_PATH: the test components)
import { mkdtempSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import path from "node:path";

import { peers, startKeel, stopKeel, until } from "./run_keel.mjs";

const { FoxgloveClient } = peers("@foxglove/ws-protocol");
const WebSocket = peers("ws");
const faults = Number(process.argv[2] || 500);
const dir = mkdtempSync(path.join(tmpdir(), "keel-latency-"));
const scenario = path.join(dir, "scenario.xml");
writeFileSync(scenario,
  `<fault_scenario><fault at="1000" component="counter" kind="throw" repeat="${faults}" every="20"/></fault_scenario>\n`);
const run = await startKeel(["tests/integration/profiles/monitor/faulty.xml", "--inject", scenario,
                             "--duration", String(1 + faults * 0.02 + 5)]);
const nowNs = () => BigInt(Math.round((performance.timeOrigin + performance.now()) * 1e3)) * 1000n;
const ws = new WebSocket(`ws://${run.host}/`, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const client = new FoxgloveClient({ ws });
let start;
const topics = new Map();
const lat = [];
const decoder = new TextDecoder();
client.on("serverInfo", (i) => (start = BigInt(i.metadata.start_unix_ns)));
client.on("advertise", (chs) => { for (const c of chs) topics.set(client.subscribe(c.id), c.topic); });
client.on("message", ({ subscriptionId, data }) => {
  const received = nowNs();
  if (topics.get(subscriptionId) !== "/keel/faults") return;
  const r = JSON.parse(decoder.decode(data));
  if (r.event === "detected" && r.t_ns > 500e6) lat.push(Number(received - (start + BigInt(r.t_ns))) / 1e3);
});
await until(() => (lat.length >= faults ? true : undefined), `${faults} detections`, 120000).catch(() => {});
await stopKeel(run);
rmSync(dir, { recursive: true });
lat.sort((a, b) => a - b);
const q = (p) => lat[Math.min(lat.length - 1, Math.floor(p * lat.length))];
console.log(`detections received: ${lat.length}; from the record's time to the client, µs: ` +
  `p50 ${q(0.5).toFixed(0)}, p99 ${q(0.99).toFixed(0)}, max ${lat.at(-1).toFixed(0)}`);
process.exit(0);
