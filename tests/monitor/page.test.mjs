// The monitor's web page (src/monitor/page/index.html) in a real browser: Debian's headless
// Chromium driven by puppeteer-core, against `keel run APP.xml --monitor 127.0.0.1:0` when
// KEEL_CLI names the keel command, else against tests/monitor/mock_server.mjs (Foxglove's own
// server class playing a scripted run). Either prints `monitor: http://127.0.0.1:PORT/?token=T`.
//
// Beside the browser, an independent Foxglove client (@foxglove/ws-protocol's FoxgloveClient on
// `ws`) watches the same server: it is the oracle for what the page should show (the components,
// the faults' records) and makes the token-less service calls the page cannot make.
//
//   node --test tests/monitor/page.test.mjs                       # the mock
//   KEEL_CLI=build/bin/keel node --test tests/monitor/page.test.mjs
//     KEEL_MONITOR_PROFILE  the profile keel runs    (default examples/02_fault_detection/app.xml)
//     KEEL_MONITOR_SCENARIO its fault scenario       (default: a segfault of avoider at 4 s)
//     KEEL_MONITOR_CRASH    the injected kind the fault row test waits for (default segfault)
//   KEEL_MONITOR_SHOT       the screenshot's path     (default /tmp/keel-monitor.png)
//
// Modules: tests/peers/node_modules (scripts/peers.sh installs them), resolved by run_keel.mjs's
// peers(): no NODE_PATH, and any working directory works. The server is started by its serve().
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { mkdtempSync, writeFileSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";

import { peers, repo as ROOT, serve, stopKeel } from "./run_keel.mjs";

const puppeteer = peers("puppeteer-core");
const { FoxgloveClient } = peers("@foxglove/ws-protocol");
const WebSocket = peers("ws");

const CHROMIUM = process.env.KEEL_CHROMIUM || "/usr/bin/chromium";
const SHOT = process.env.KEEL_MONITOR_SHOT || "/tmp/keel-monitor.png";
const CRASH = process.env.KEEL_MONITOR_CRASH || "segfault";
const TEST = { timeout: 30000, polling: 100 };

// ------------------------------------------------------------------ the server
let server;       // what serve() started
let tmp;          // temporary directory (keel mode)
let base;         // http://127.0.0.1:PORT/
let token;

async function startServer() {
  let cmd, args;
  if (process.env.KEEL_CLI) {
    tmp = mkdtempSync(path.join(tmpdir(), "keel-monitor-"));
    let scenario = process.env.KEEL_MONITOR_SCENARIO;
    if (!scenario) {
      scenario = path.join(tmp, "scenario.xml");
      writeFileSync(scenario, `<?xml version="1.0" encoding="UTF-8"?>
<fault_scenario>
  <fault at="4000" component="avoider" kind="segfault"/>
</fault_scenario>
`);
    }
    cmd = path.resolve(ROOT, process.env.KEEL_CLI);
    args = ["run", process.env.KEEL_MONITOR_PROFILE || "examples/02_fault_detection/app.xml",
      "--inject", scenario, "--monitor", "127.0.0.1:0", "--duration", "120", "--log", path.join(tmp, "run.jsonl")];
  } else {
    cmd = process.execPath;
    args = [fileURLToPath(new URL("mock_server.mjs", import.meta.url)), "--monitor", "127.0.0.1:0", "--fault-every", "1000"];
  }
  server = await serve(cmd, args);
  token = server.token;
  const url = new URL(server.url);
  url.search = "";
  return url.href;
}

async function stopServer() {
  if (server) await stopKeel(server);
}

// ------------------------------------------------------------------ the oracle
// Records what the server says: the latest /keel/state, every /keel/faults record, channels and
// services; answers service calls.
function oracleClient(url) {
  const ws = new WebSocket(url.replace(/^http/, "ws"), [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const client = new FoxgloveClient({ ws });
  const dec = new TextDecoder();
  const o = { client, state: null, records: [], channels: new Map(), services: new Map(), topics: new Map(), waiters: [] };
  const wake = () => { o.waiters = o.waiters.filter((w) => !w()); };
  // Every handler before the first await: ws emits all frames of one read at once.
  client.on("advertise", (chs) => {
    for (const c of chs) {
      o.channels.set(c.id, c);
      if (c.topic === "/keel/state" || c.topic === "/keel/faults") o.topics.set(client.subscribe(c.id), c.topic);
    }
    wake();
  });
  client.on("advertiseServices", (ss) => { for (const s of ss) o.services.set(s.name, s); wake(); });
  client.on("message", ({ subscriptionId, data }) => {
    const m = JSON.parse(dec.decode(data));
    const topic = o.topics.get(subscriptionId);
    if (topic === "/keel/state") o.state = m;
    else if (topic === "/keel/faults") o.records.push(m);
    wake();
  });
  o.until = (pred, what, ms = 10000) => new Promise((resolve, reject) => {
    const t = setTimeout(() => reject(new Error(`oracle: no ${what} within ${ms} ms`)), ms);
    const w = () => { const v = pred(); if (v) { clearTimeout(t); resolve(v); return true; } return false; };
    if (!w()) o.waiters.push(w);
  });
  let nextCall = 1;
  o.call = (name, request) => new Promise((resolve, reject) => {
    const s = o.services.get(name);
    if (!s) return reject(new Error(`oracle: no service ${name}`));
    const callId = nextCall++;
    const t = setTimeout(() => reject(new Error(`oracle: no answer to ${name}`)), 10000);
    const done = (v) => { clearTimeout(t); client.off("serviceCallResponse", ok); client.off("serviceCallFailure", fail); resolve(v); };
    const ok = (r) => { if (r.callId === callId) done({ ok: true, body: JSON.parse(dec.decode(r.data)) }); };
    const fail = (r) => { if (r.callId === callId) done({ ok: false, message: r.message }); };
    client.on("serviceCallResponse", ok);
    client.on("serviceCallFailure", fail);
    client.sendServiceCallRequest({ serviceId: s.id, callId, encoding: "json", data: new TextEncoder().encode(JSON.stringify(request)) });
  });
  o.close = () => client.close();
  return o;
}

// ------------------------------------------------------------------ browser
let browser, oracle, viewer;  // viewer: the page opened without the token
const problems = [];          // the page's own errors, checked at the end

async function openPage(url) {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 900 });
  page.on("pageerror", (e) => problems.push(`page error: ${e.message}`));
  page.on("console", (m) => { if (m.type() === "error") problems.push(`console error: ${m.text()}`); });
  await page.goto(url, { waitUntil: "load" });
  return page;
}
const textOf = (page, sel) => page.$eval(sel, (e) => e.textContent.trim());
const faultsText = (n) => `${n} fault${n === 1 ? "" : "s"}`;

before(async () => {
  base = await startServer();
  oracle = oracleClient(base);
  browser = await puppeteer.launch({
    executablePath: CHROMIUM, headless: true,
    args: ["--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1280,900"],
  });
  viewer = await openPage(base);
});

after(async () => {
  if (browser) await browser.close();
  if (oracle) oracle.close();
  await stopServer();
  if (tmp) rmSync(tmp, { recursive: true, force: true });
});

// ------------------------------------------------------------------ tests
test("every component appears with its state name and fault count as text", TEST, async () => {
  const state = await oracle.until(() => oracle.state && oracle.state.components.length && oracle.state, "/keel/state");
  for (const c of state.components) await viewer.waitForSelector(`#graph [data-component="${c.name}"]`, { timeout: 5000 });
  // The page and the oracle see the same run (compared until a moment when neither is changing).
  let diff;
  for (const deadline = Date.now() + 8000; Date.now() < deadline; await new Promise((r) => setTimeout(r, 100))) {
    const shown = await viewer.$$eval("#graph [data-component]", (bs) => bs.map((b) => ({
      name: b.getAttribute("data-component"), state: b.getAttribute("data-state"),
      // The visible text only: not the tooltip (<title>), which a sighted user does not see.
      faults: Number(b.getAttribute("data-faults")), text: [...b.querySelectorAll("text")].map((t) => t.textContent).join(" ") })));
    const want = oracle.state.components;
    diff = [];
    if (shown.length !== want.length) diff.push(`page shows ${shown.length} components, the run has ${want.length}`);
    for (const c of want) {
      const s = shown.find((x) => x.name === c.name);
      if (!s) { diff.push(`${c.name} missing`); continue; }
      if (s.state !== c.state || s.faults !== c.faults) diff.push(`${c.name}: page ${s.state}/${s.faults}, run ${c.state}/${c.faults}`);
      // As text, not by colour alone: the box says its state and its fault count.
      if (!s.text.includes(c.state)) diff.push(`${c.name}: box text '${s.text}' lacks the state name ${c.state}`);
      if (!s.text.includes(faultsText(c.faults))) diff.push(`${c.name}: box text '${s.text}' lacks '${faultsText(c.faults)}'`);
      const row = await viewer.$eval(`#counts tr[data-row-component="${c.name}"]`, (r) => r.textContent).catch(() => "");
      if (!row.includes(c.state) || !row.includes(String(c.faults))) diff.push(`${c.name}: fault counts row '${row}'`);
    }
    if (!diff.length) break;
  }
  assert.deepEqual(diff, []);
  assert.ok((await textOf(viewer, "#run-name")).length > 1, "the run's name is shown");
  assert.equal(await viewer.$eval("#connection", (e) => e.dataset.status), "connected");
});

test("without the token the controls are disabled and keel refuses a call", TEST, async () => {
  await oracle.until(() => oracle.services.has("/keel/emergency_stop"), "emergency service");
  for (const id of ["#emergency-stop", "#clear-emergency"]) {
    const b = await viewer.$eval(id, (e) => ({ disabled: e.disabled, title: e.title }));
    assert.equal(b.disabled, true, `${id} is disabled without the token`);
    assert.match(b.title, /read-only: open the URL keel run printed \(with \?token=\) to control/);
  }
  assert.match(await textOf(viewer, "#control-result"), /read-only/i, "the page says why");
  // What the disabled button would have sent, sent anyway: refused, and nothing latched.
  const none = await oracle.call("/keel/emergency_stop", {});
  assert.equal(none.ok, false, "a call without a token is refused");
  assert.match(none.message, /token/);
  const bad = await oracle.call("/keel/emergency_stop", { token: "0".repeat(32) });
  assert.equal(bad.ok, false, "a call with a wrong token is refused");
  assert.match(bad.message, /token/);
  await new Promise((r) => setTimeout(r, 300));
  assert.equal(oracle.state.emergency, false, "no emergency latched");
  assert.equal(await textOf(viewer, "#emergency"), "not latched");
});

test("an injected crash appears in the timeline with its latencies", TEST, async () => {
  const sel = `#timeline tr[data-fault-id][data-injected-kind="${CRASH}"][data-detection-us]`;
  const row = await viewer.waitForSelector(sel, { timeout: 20000 });
  const shown = await row.evaluate((r) => ({
    id: r.getAttribute("data-fault-id"), component: r.getAttribute("data-fault-component"),
    detection: Number(r.getAttribute("data-detection-us")), text: r.textContent }));
  // The oracle's records of that fault give the latency the page must show.
  const recs = await oracle.until(() => {
    const rs = oracle.records.filter((r) => String(r.fault_id) === shown.id);
    return rs.some((r) => r.event === "detected") && rs.some((r) => r.event === "injected") && rs;
  }, `records of fault ${shown.id}`);
  const injected = recs.find((r) => r.event === "injected"), detected = recs.find((r) => r.event === "detected");
  assert.equal(shown.component, detected.component);
  assert.ok(Math.abs(shown.detection - (detected.t_ns - injected.t_ns) / 1000) < 0.01, `detection ${shown.detection} µs`);
  assert.ok(shown.text.includes(detected.component) && shown.text.includes(detected.kind), `row text: ${shown.text}`);
  assert.match(shown.text, /\d+(\.\d+)? (µs|ms|s)/, "the latency is shown as text");
  // When it recovers, the recovery latency is the recovered record's latency_us.
  const recovered = await oracle.until(() => oracle.records.find((r) => String(r.fault_id) === shown.id && r.event === "recovered"),
    `recovery of fault ${shown.id}`, 5000).catch(() => null);
  if (recovered) {
    await viewer.waitForSelector(`#timeline tr[data-fault-id="${shown.id}"][data-recovery-us]`, { timeout: 3000 });
    const us = Number(await viewer.$eval(`#timeline tr[data-fault-id="${shown.id}"]`, (r) => r.getAttribute("data-recovery-us")));
    assert.ok(Math.abs(us - recovered.latency_us) < 0.01, `recovery ${us} µs, the record says ${recovered.latency_us}`);
  }
  // The component's count went up with it.
  const n = await viewer.$eval(`#graph [data-component="${shown.component}"]`, (b) => Number(b.getAttribute("data-faults")));
  assert.ok(n >= 1, `${shown.component} shows ${n} faults`);
});

test("with the token, emergency stop latches and clear unlatches", TEST, async () => {
  const page = await openPage(`${base}?token=${token}`);
  try {
    assert.equal(await page.evaluate(() => location.search.includes("token")), false, "the token left the address bar");
    await page.waitForSelector("#emergency-stop:not([disabled])", { timeout: 5000 });
    await page.waitForFunction(() => document.querySelector("#emergency").textContent.trim() === "not latched", { timeout: 5000, polling: 100 });
    await page.click("#emergency-stop");
    await page.waitForFunction(() => document.querySelector("#emergency").textContent.trim() === "latched", { timeout: 5000, polling: 100 });
    await page.waitForFunction(() => /done/.test(document.querySelector("#control-result").textContent), { timeout: 5000, polling: 100 });
    await oracle.until(() => oracle.state.emergency === true, "a latched emergency in /keel/state", 3000);
    // The read-only page sees it too.
    await viewer.waitForFunction(() => document.querySelector("#emergency").textContent.trim() === "latched", { timeout: 3000, polling: 100 });
    await page.click("#clear-emergency");
    await page.waitForFunction(() => document.querySelector("#emergency").textContent.trim() === "not latched", { timeout: 5000, polling: 100 });
    await oracle.until(() => oracle.state.emergency === false, "a cleared emergency in /keel/state", 3000);
  } finally {
    await page.close();
  }
});

test("a port's value is shown on demand", TEST, async (t) => {
  const port = [...oracle.channels.values()].find((c) => c.topic.startsWith("/keel/ports/"));
  if (!port) return t.skip("the server advertises no port channel");
  const [, component] = /^\/keel\/ports\/(.*)\/[^/]+$/.exec(port.topic);
  const page = await openPage(`${base}?token=${token}`);
  try {
    await (await page.waitForSelector(`#graph [data-component="${component}"]`, { timeout: 5000 })).click();
    await (await page.waitForSelector(`#details button[data-topic="${port.topic}"]`, { timeout: 3000 })).click();
    const value = await page.waitForFunction((topic) => {
      const box = document.querySelector(`[data-value-for="${topic}"]`);
      return box && !/waiting/.test(box.textContent) && box.textContent;
    }, { timeout: 5000, polling: 100 }, port.topic);
    assert.ok((await value.jsonValue()).length > 0);
    await page.waitForFunction(() => document.querySelector("#timeline tr[data-recovery-us]"), { timeout: 10000, polling: 100 }).catch(() => {});
    await page.screenshot({ path: SHOT });
    await page.click(`#details button[data-topic="${port.topic}"]`);
    await page.waitForFunction((topic) => !document.querySelector(`[data-value-for="${topic}"]`), { timeout: 3000, polling: 100 }, port.topic);
  } finally {
    await page.close();
  }
});

test("the page logged no error of its own", TEST, () => {
  assert.deepEqual(problems, []);
});
