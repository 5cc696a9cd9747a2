"use strict";
(() => {
  // ---------------------------------------------------------------- constants
  const SUBPROTOCOL = "foxglove.websocket.v1";
  const MAX_FAULTS = 500;     // timeline rows kept (oldest dropped)
  const MAX_EVENTS = 200;     // run events kept
  const MAX_STATUS = 6;       // server status messages shown
  const CALL_TIMEOUT_MS = 10000;
  const READ_ONLY = "read-only: open the URL keel run printed (with ?token=) to control";
  // Lifecycle states: fill, stroke, text. Any other state gets OTHER; the name is always text too.
  const STATES = {
    Active: ["#e3f4e8", "#1e7e34", "#145224"],
    Ready: ["#e4eefc", "#1a5fb4", "#123f78"],
    Created: ["#f0f2f4", "#6b7680", "#3a434c"],
    Initialized: ["#f0f2f4", "#6b7680", "#3a434c"],
    Inactive: ["#f0f2f4", "#6b7680", "#3a434c"],
    Error: ["#fde7e5", "#c5221f", "#8c1512"],
    Stopped: ["#fff3dc", "#b06000", "#6e3c00"],
    Destroyed: ["#f7f8f9", "#a3acb5", "#5b6570"],
  };
  const OTHER = ["#f1eafb", "#7b3fc4", "#4f2880"];
  const stateColours = (s) => STATES[s] || OTHER;

  // ---------------------------------------------------------------- helpers
  const $ = (id) => document.getElementById(id);
  const SVGNS = "http://www.w3.org/2000/svg";
  function el(tag, attrs, ...children) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) {
      if (v === undefined || v === null || v === false) continue;
      if (k === "class") e.className = v; else if (k === "text") e.textContent = v; else e.setAttribute(k, v);
    }
    for (const c of children) if (c !== null && c !== undefined) e.append(c);
    return e;
  }
  function svg(tag, attrs, ...children) {
    const e = document.createElementNS(SVGNS, tag);
    for (const [k, v] of Object.entries(attrs || {})) {
      if (v === undefined || v === null) continue;
      if (k === "text") e.textContent = v; else e.setAttribute(k, v);
    }
    for (const c of children) if (c) e.append(c);
    return e;
  }
  function fmtRunTime(ns) {
    if (typeof ns !== "number" || !isFinite(ns)) return "—";
    const s = ns / 1e9;
    if (s < 60) return s.toFixed(3) + " s";
    const m = Math.floor(s / 60);
    return m + ":" + (s - 60 * m).toFixed(3).padStart(6, "0");
  }
  function fmtLatency(us) {
    if (typeof us !== "number" || !isFinite(us)) return "—";
    if (us < 1000) return (us < 10 ? us.toFixed(1) : Math.round(us)) + " µs";
    if (us < 1e6) return (us / 1000).toFixed(us < 1e4 ? 2 : 1) + " ms";
    return (us / 1e6).toFixed(2) + " s";
  }
  const plural = (n, word) => n + " " + word + (n === 1 ? "" : "s");
  function shortJson(v, max) {
    let s;
    try { s = JSON.stringify(v); } catch (e) { s = String(v); }
    if (s === undefined) s = String(v);
    return s.length > max ? s.slice(0, max - 1) + "…" : s;
  }
  // Batch DOM work: at most one render per frame (or per 120 ms when frames do not run).
  const dirty = new Set();
  let renderQueued = false;
  function invalidate(what) {
    dirty.add(what);
    if (renderQueued) return;
    renderQueued = true;
    let done = false;
    const run = () => { if (done) return; done = true; renderQueued = false; render(); };
    requestAnimationFrame(run);
    setTimeout(run, 120);
  }

  // ---------------------------------------------------------------- token
  let token = null;
  {
    const params = new URLSearchParams(location.search);
    if (params.has("token")) {
      token = params.get("token") || null;
      params.delete("token");
      const rest = params.toString();
      history.replaceState(history.state, "", location.pathname + (rest ? "?" + rest : "") + location.hash);
      // Per tab only (gone with the tab), so a reload keeps control; never in the address bar.
      try { if (token) sessionStorage.setItem("keel.monitor.token", token); } catch (e) { /* storage off */ }
    } else {
      try { token = sessionStorage.getItem("keel.monitor.token"); } catch (e) { token = null; }
    }
  }

  // ---------------------------------------------------------------- model
  const model = {
    session: null, runName: "", serverInfo: null,
    state: null,              // last /keel/state payload
    stateT: -Infinity,
    emergency: null, emergencyT: -Infinity,
    faults: new Map(),        // fault_id -> fault
    faultOrder: [],           // fault ids, oldest first
    events: [],
    selected: null,           // component name
    lastT: null,              // newest t_ns seen (run time)
  };
  const conn = {
    ws: null, attempt: 0, timer: null, status: "connecting",
    channels: new Map(),      // channel id -> channel
    subs: new Map(),          // subscription id -> {channelId, topic}
    subByTopic: new Map(),    // topic -> subscription id
    nextSub: 1,
    services: new Map(),      // name -> service
    calls: new Map(),         // call id -> {name, timer}
    nextCall: 1,
  };
  const watched = new Map();  // port topic -> {component, port, value, t, gone}

  // ---------------------------------------------------------------- connection
  function setConnection(status, text) {
    conn.status = status;
    const c = $("connection");
    c.dataset.status = status;
    c.textContent = text;
    $("main").classList.toggle("stale", status !== "connected" || !model.state);
    // The latch as last seen: not known while disconnected.
    $("emergency").classList.toggle("stale", status !== "connected");
    $("emergency").title = status === "connected" ? "" : "last known state: not connected to keel";
    updateControls();
  }

  function connect() {
    clearTimeout(conn.timer);
    conn.channels.clear(); conn.subs.clear(); conn.subByTopic.clear(); conn.services.clear();
    conn.nextSub = 1;
    for (const w of watched.values()) w.sub = null;
    let ws;
    try {
      ws = new WebSocket((location.protocol === "https:" ? "wss://" : "ws://") + location.host + "/", [SUBPROTOCOL]);
    } catch (e) {
      scheduleReconnect("cannot connect: " + e.message);
      return;
    }
    ws.binaryType = "arraybuffer";
    conn.ws = ws;
    setConnection(conn.attempt ? "reconnecting" : "connecting", conn.attempt ? "reconnecting…" : "connecting…");
    ws.onopen = () => {
      if (ws.protocol && ws.protocol !== SUBPROTOCOL) {
        ws.close(1002, "wrong subprotocol");
      }
    };
    ws.onmessage = (ev) => {
      if (conn.ws !== ws) return;
      try {
        if (typeof ev.data === "string") onJson(JSON.parse(ev.data));
        else onBinary(ev.data);
      } catch (e) {
        console.error("keel monitor: bad message", e);
      }
    };
    ws.onclose = (ev) => {
      if (conn.ws !== ws) return;
      conn.ws = null;
      failPendingCalls("connection closed before keel answered");
      scheduleReconnect(ev.reason ? "closed: " + ev.reason : "connection lost");
    };
    ws.onerror = () => { /* onclose follows */ };
  }

  function scheduleReconnect(why) {
    conn.attempt += 1;
    const delay = Math.min(10000, 500 * 2 ** Math.min(conn.attempt - 1, 5));
    const until = Date.now() + delay;
    const tick = () => {
      const left = Math.max(0, Math.ceil((until - Date.now()) / 1000));
      setConnection("reconnecting", why + " · retry in " + left + " s");
      if (left > 0) conn.timer = setTimeout(tick, 1000);
    };
    tick();
    conn.timer = setTimeout(connect, delay);
  }

  function send(obj) {
    if (conn.ws && conn.ws.readyState === WebSocket.OPEN) conn.ws.send(JSON.stringify(obj));
  }

  function subscribe(channel) {
    if (conn.subByTopic.has(channel.topic)) return conn.subByTopic.get(channel.topic);
    const id = conn.nextSub++;
    conn.subs.set(id, { channelId: channel.id, topic: channel.topic });
    conn.subByTopic.set(channel.topic, id);
    send({ op: "subscribe", subscriptions: [{ id, channelId: channel.id }] });
    return id;
  }
  function unsubscribe(topic) {
    const id = conn.subByTopic.get(topic);
    if (id === undefined) return;
    conn.subByTopic.delete(topic);
    conn.subs.delete(id);
    send({ op: "unsubscribe", subscriptionIds: [id] });
  }
  const channelByTopic = (topic) => {
    for (const c of conn.channels.values()) if (c.topic === topic) return c;
    return null;
  };

  function onJson(m) {
    switch (m.op) {
      case "serverInfo": {
        const session = m.sessionId || "";
        if (model.session !== null && session !== model.session) resetRun();
        model.session = session;
        model.serverInfo = m;
        const meta = m.metadata || {};
        if (meta.run) model.runName = meta.run;
        conn.attempt = 0;
        setConnection("connected", "connected");
        invalidate("header");
        break;
      }
      case "advertise":
        for (const c of m.channels || []) {
          // A topic advertised again under a new id replaces the old channel.
          for (const [id, old] of conn.channels) if (old.topic === c.topic && id !== c.id) dropChannel(id);
          conn.channels.set(c.id, c);
          if (c.topic === "/keel/state" || c.topic === "/keel/faults") subscribe(c);
          else if (watched.has(c.topic)) { watched.get(c.topic).gone = false; subscribe(c); }
        }
        invalidate("details");
        break;
      case "unadvertise":
        for (const id of m.channelIds || []) dropChannel(id);
        invalidate("details");
        break;
      case "advertiseServices":
        for (const s of m.services || []) conn.services.set(s.name, s);
        updateControls();
        break;
      case "unadvertiseServices":
        for (const id of m.serviceIds || []) for (const [n, s] of conn.services) if (s.id === id) conn.services.delete(n);
        updateControls();
        break;
      case "status":
        addStatus(m);
        break;
      case "removeStatus":
        for (const id of m.statusIds || []) removeStatus(id);
        break;
      case "serviceCallFailure": {
        const call = conn.calls.get(m.callId);
        if (!call) break;
        clearTimeout(call.timer);
        conn.calls.delete(m.callId);
        showResult("refused", call.label + " refused: " + (m.message || "no reason given"));
        break;
      }
      default:
        break;  // ops for capabilities keel does not announce
    }
  }

  function dropChannel(id) {
    const c = conn.channels.get(id);
    if (!c) return;
    conn.channels.delete(id);
    const sub = conn.subByTopic.get(c.topic);
    if (sub !== undefined) { conn.subByTopic.delete(c.topic); conn.subs.delete(sub); }
    const w = watched.get(c.topic);
    if (w) { w.gone = true; invalidate("ports"); }
  }

  const decoder = new TextDecoder();
  function onBinary(buf) {
    const v = new DataView(buf);
    if (v.byteLength < 1) return;
    const op = v.getUint8(0);
    if (op === 0x01 && v.byteLength >= 13) {
      const sub = conn.subs.get(v.getUint32(1, true));
      if (!sub) return;  // unsubscribed meanwhile
      const payload = JSON.parse(decoder.decode(new Uint8Array(buf, 13)));
      if (sub.topic === "/keel/state") onState(payload);
      else if (sub.topic === "/keel/faults") onRecord(payload);
      else onPort(sub.topic, payload);
    } else if (op === 0x03 && v.byteLength >= 13) {
      const callId = v.getUint32(5, true);
      const encLen = v.getUint32(9, true);
      if (13 + encLen > v.byteLength) return;
      const call = conn.calls.get(callId);
      if (!call) return;
      clearTimeout(call.timer);
      conn.calls.delete(callId);
      let res = null;
      try { res = JSON.parse(decoder.decode(new Uint8Array(buf, 13 + encLen))); } catch (e) { res = null; }
      if (res && res.ok) showResult("ok", call.label + ": done" + (res.detail ? " — " + res.detail : ""));
      else showResult("error", call.label + " failed" + (res && res.detail ? ": " + res.detail : ""));
    }
  }

  // ---------------------------------------------------------------- services
  function callService(name, label) {
    const s = conn.services.get(name);
    if (!s || !token || !conn.ws) return;
    const callId = conn.nextCall++;
    const enc = new TextEncoder();
    const encoding = enc.encode("json");
    const payload = enc.encode(JSON.stringify({ token }));
    const buf = new ArrayBuffer(13 + encoding.length + payload.length);
    const v = new DataView(buf);
    v.setUint8(0, 0x02);
    v.setUint32(1, s.id, true);
    v.setUint32(5, callId, true);
    v.setUint32(9, encoding.length, true);
    new Uint8Array(buf, 13, encoding.length).set(encoding);
    new Uint8Array(buf, 13 + encoding.length).set(payload);
    const timer = setTimeout(() => {
      if (!conn.calls.delete(callId)) return;
      showResult("error", label + ": no answer from keel within " + CALL_TIMEOUT_MS / 1000 + " s");
    }, CALL_TIMEOUT_MS);
    conn.calls.set(callId, { name, label, timer });
    conn.ws.send(buf);
    showResult("pending", label + ": sent…");
  }
  function failPendingCalls(why) {
    for (const c of conn.calls.values()) { clearTimeout(c.timer); showResult("error", c.label + ": " + why); }
    conn.calls.clear();
  }
  function showResult(kind, text) {
    const r = $("control-result");
    r.dataset.kind = kind;
    r.textContent = text;
  }
  function updateControls() {
    const pairs = [["emergency-stop", "/keel/emergency_stop"], ["clear-emergency", "/keel/clear_emergency"]];
    for (const [id, name] of pairs) {
      const b = $(id);
      let why = "";
      if (!token) why = READ_ONLY;
      else if (conn.status !== "connected") why = "not connected to keel";
      else if (!conn.services.has(name)) why = "keel does not offer " + name;
      b.disabled = why !== "";
      b.title = why || (id === "emergency-stop" ? "Latch keel's emergency stop (" + name + ")" : "Clear the emergency latch (" + name + ")");
    }
    if (!token) showResult("readonly", "Read-only — open the URL keel run printed (with ?token=) to control.");
  }
  $("emergency-stop").addEventListener("click", () => callService("/keel/emergency_stop", "Emergency stop"));
  $("clear-emergency").addEventListener("click", () => callService("/keel/clear_emergency", "Clear emergency"));

  // ---------------------------------------------------------------- status messages
  const statuses = [];
  function addStatus(m) {
    const id = m.id || null;
    if (id) removeStatus(id, true);
    statuses.unshift({ id, level: m.level | 0, message: String(m.message || ""), at: new Date() });
    statuses.length = Math.min(statuses.length, MAX_STATUS);
    invalidate("status");
  }
  function removeStatus(id, quiet) {
    const i = statuses.findIndex((s) => s.id === id);
    if (i >= 0) statuses.splice(i, 1);
    if (!quiet) invalidate("status");
  }

  // ---------------------------------------------------------------- data
  function noteTime(t) {
    if (typeof t === "number" && (model.lastT === null || t > model.lastT)) { model.lastT = t; invalidate("header"); }
  }
  function onState(s) {
    if (!s || !Array.isArray(s.components)) return;
    const t = typeof s.t_ns === "number" ? s.t_ns : model.stateT;
    if (t < model.stateT) return;  // an older snapshot overtaken by a newer one
    const structure = (x) => x ? JSON.stringify([x.components.map((c) => [c.name, c.application]), x.connections || []]) : "";
    const relayout = structure(model.state) !== structure(s);
    model.state = s;
    model.stateT = t;
    if (s.run) model.runName = s.run;
    if (typeof s.emergency === "boolean" && t >= model.emergencyT) { model.emergency = s.emergency; model.emergencyT = t; }
    noteTime(s.t_ns);
    if (model.selected && !s.components.some((c) => c.name === model.selected)) model.selected = null;
    $("main").classList.toggle("stale", conn.status !== "connected");
    invalidate(relayout ? "layout" : "graph");
    invalidate("counts"); invalidate("details"); invalidate("header");
  }

  function onRecord(r) {
    if (!r || typeof r !== "object") return;
    noteTime(r.t_ns);
    const t = typeof r.t_ns === "number" ? r.t_ns : null;
    if (r.event === "emergency" && (r.phase === "latched" || r.phase === "cleared")) {
      if (t === null || t >= model.emergencyT) { model.emergency = r.phase === "latched"; model.emergencyT = t ?? model.emergencyT; }
      invalidate("header");
    }
    const id = r.fault_id;
    if ((typeof id === "number" || typeof id === "string") && r.event !== "counts" &&
        !(r.event === "state" && r.application !== undefined)) {
      faultRecord(r);
    }
    if (isRunEvent(r)) addEvent(r);
  }

  function isRunEvent(r) {
    switch (r.event) {
      case "engine": case "emergency": case "warning": case "host": case "end_requested": return true;
      case "action": return r.fault_id === undefined;  // emergency stop / clear by an operator
      case "state": return r.application !== undefined;  // an application stopped
      case "armed": case "injected": case "detected": case "diagnosed": case "recovered": case "counts": return false;
      default: return r.event !== "state" && r.fault_id === undefined;  // the run's end record, future events
    }
  }

  function faultRecord(r) {
    const id = String(r.fault_id);
    let f = model.faults.get(id);
    if (!f) {
      f = { id, component: r.component || "", firstT: r.t_ns, actions: [], states: [], fresh: true };
      model.faults.set(id, f);
      model.faultOrder.push(id);
      while (model.faultOrder.length > MAX_FAULTS) {
        const old = model.faultOrder.shift();
        model.faults.delete(old);
        dropRows.push(old);
      }
    }
    if (!f.component && r.component) f.component = r.component;
    if (typeof r.t_ns === "number" && !(r.t_ns >= f.firstT)) f.firstT = r.t_ns;
    switch (r.event) {
      case "armed": f.armed = r; break;
      case "injected": f.injected = r; if (r.detected === false) f.notDetected = true; break;
      case "detected": f.detected = r; break;
      case "diagnosed": f.diagnosed = r; break;
      case "action": f.actions.push(r); f.actions.sort((a, b) => (a.t_ns ?? 0) - (b.t_ns ?? 0)); break;
      case "recovered": f.recovered = r; break;
      case "state": f.states.push(r); break;
      default: (f.other ||= []).push(r); break;
    }
    dirtyFaults.add(id);
    invalidate("timeline");
  }
  const dirtyFaults = new Set();
  const dropRows = [];

  function faultView(f) {
    const d = f.detected;
    const kind = (d && d.kind) || (f.armed && f.armed.kind) || (f.injected && f.injected.kind) || "";
    const injectedKind = (f.armed && f.armed.kind) || (f.injected && f.injected.kind) || "";
    let detectionUs = null, recoveryUs = null;
    if (d && f.injected && typeof d.t_ns === "number" && typeof f.injected.t_ns === "number") {
      detectionUs = (d.t_ns - f.injected.t_ns) / 1000;
    }
    if (f.recovered) {
      if (typeof f.recovered.latency_us === "number") recoveryUs = f.recovered.latency_us;
      else if (d && typeof f.recovered.t_ns === "number" && typeof d.t_ns === "number") recoveryUs = (f.recovered.t_ns - d.t_ns) / 1000;
    }
    let outcome = "in progress";
    const handling = f.diagnosed && f.diagnosed.handling;
    if (f.recovered) outcome = "recovered";
    else if (f.notDetected) outcome = "not detected";
    else if (f.actions.some((a) => a.outcome === "failed")) outcome = "failed";
    else if (f.injected && f.injected.hardware && !d) outcome = f.injected.outcome ? "refused" : "injected";
    else if (handling === "ignore") outcome = "ignored";
    else if (handling === "done") outcome = "handled";
    else if (f.actions.some((a) => a.action === "emergency_stop")) outcome = "emergency";
    else if (f.actions.some((a) => a.action === "stop")) outcome = "stopped";
    else if (f.actions.some((a) => a.action === "replace" && a.outcome === "ok")) outcome = "replaced";
    return { kind, injectedKind, detectionUs, recoveryUs, outcome };
  }

  function onPort(topic, p) {
    const w = watched.get(topic);
    if (!w) return;
    w.value = p && Object.prototype.hasOwnProperty.call(p, "value") ? p.value : p;
    w.t = p && typeof p.t_ns === "number" ? p.t_ns : null;
    w.count = (w.count || 0) + 1;
    w.gone = false;
    noteTime(w.t);
    invalidate("ports");
  }

  function addEvent(r) {
    model.events.unshift(r);
    if (model.events.length > MAX_EVENTS) model.events.length = MAX_EVENTS;
    invalidate("events");
  }

  function resetRun() {
    // A new sessionId: another keel run. Nothing of the old one applies.
    model.state = null; model.stateT = -Infinity; model.emergency = null; model.emergencyT = -Infinity;
    model.faults.clear(); dropRows.push(...model.faultOrder); model.faultOrder = []; model.events = [];
    model.lastT = null; model.runName = "";
    for (const w of watched.values()) { w.value = undefined; w.t = null; w.count = 0; }
    statuses.length = 0;
    for (const k of ["layout", "counts", "details", "timeline", "events", "header", "status"]) invalidate(k);
  }

  // ---------------------------------------------------------------- component name resolution
  function components() { return model.state ? model.state.components : []; }
  function resolveName(name, near) {
    // Connections may name an instance relative to its application ("counter" for "pair.counter").
    const cs = components();
    if (cs.some((c) => c.name === name)) return name;
    const cands = cs.filter((c) => c.name.endsWith("." + name));
    if (cands.length === 1) return cands[0].name;
    if (cands.length > 1 && near) {
      const app = (cs.find((c) => c.name === near) || {}).application;
      const same = cands.find((c) => c.application === app);
      if (same) return same.name;
    }
    return cands.length ? cands[0].name : null;
  }
  function edges() {
    const out = [];
    for (const e of (model.state && model.state.connections) || []) {
      const from = resolveName(e.from, resolveName(e.to));
      const to = resolveName(e.to, from);
      if (from && to) out.push({ from, to, fromPort: e.from_port || "", toPort: e.to_port || "" });
    }
    return out;
  }

  // ---------------------------------------------------------------- graph
  const BOX_W = 184, BOX_H = 60, COL_GAP = 76, ROW_GAP = 16, LANE_PAD = 12, LANE_HEAD = 22, MARGIN = 12, BAND_GAP = 30;
  let layout = null;  // {pos: Map name -> {x,y}, boxes: Map name -> g}

  function computeLayout() {
    const cs = components();
    const names = cs.map((c) => c.name);
    const es = edges();
    // Depth: longest path from a source, with back edges (cycles) left out.
    const succ = new Map(names.map((n) => [n, []]));
    for (const e of es) if (e.from !== e.to) succ.get(e.from).push(e.to);
    const mark = new Map(), back = new Set();
    const dfs = (n) => {
      mark.set(n, 1);
      for (const m of succ.get(n)) {
        if (mark.get(m) === 1) back.add(n + "\u0000" + m);
        else if (!mark.has(m)) dfs(m);
      }
      mark.set(n, 2);
    };
    for (const n of names) if (!mark.has(n)) dfs(n);
    const indeg = new Map(names.map((n) => [n, 0]));
    for (const [n, ms] of succ) for (const m of ms) if (!back.has(n + "\u0000" + m)) indeg.set(m, indeg.get(m) + 1);
    const depth = new Map(names.map((n) => [n, 0]));
    const queue = names.filter((n) => indeg.get(n) === 0);
    while (queue.length) {
      const n = queue.shift();
      for (const m of succ.get(n)) {
        if (back.has(n + "\u0000" + m)) continue;
        depth.set(m, Math.max(depth.get(m), depth.get(n) + 1));
        indeg.set(m, indeg.get(m) - 1);
        if (indeg.get(m) === 0) queue.push(m);
      }
    }
    // Lanes: one per application, in the plan's order; columns by depth; in a column, ordered by
    // the rows of the component's predecessors (fewer crossings), then the plan's order.
    const lanes = [];
    const laneOf = new Map();
    for (const c of cs) {
      const app = c.application || "";
      if (!laneOf.has(app)) { laneOf.set(app, { app, cols: new Map() }); lanes.push(laneOf.get(app)); }
      const lane = laneOf.get(app);
      const d = depth.get(c.name);
      if (!lane.cols.has(d)) lane.cols.set(d, []);
      lane.cols.get(d).push(c.name);
    }
    const pred = new Map(names.map((n) => [n, []]));
    for (const e of es) if (e.from !== e.to) pred.get(e.to).push(e.from);
    const row = new Map();
    const maxDepth = Math.max(0, ...depth.values());
    const pos = new Map();
    let y = MARGIN;
    const lanesOut = [];
    // A long chain wraps into bands of as many columns as the panel shows: the whole graph is in
    // view, at full size, without scrolling sideways.
    const avail = Math.max(BOX_W, $("graph-wrap").clientWidth - 2);
    const perBand = Math.max(1, Math.floor((avail - 2 * MARGIN - 2 * LANE_PAD + COL_GAP) / (BOX_W + COL_GAP)));
    const bands = Math.ceil((maxDepth + 1) / perBand);
    for (const lane of lanes) {
      let rows = 1;
      for (let d = 0; d <= maxDepth; d++) {
        const col = lane.cols.get(d);
        if (!col) continue;
        const bary = (n) => {
          const ps = pred.get(n).filter((p) => row.has(p));
          return ps.length ? ps.reduce((a, p) => a + row.get(p), 0) / ps.length : Infinity;
        };
        const order = names.indexOf.bind(names);
        col.sort((a, b) => (bary(a) - bary(b)) || (order(a) - order(b)));
        col.forEach((n, i) => row.set(n, i));
        rows = Math.max(rows, col.length);
      }
      const top = y, inner = top + LANE_HEAD;
      // Each band as tall as its tallest column.
      const bandRows = new Array(bands).fill(0);
      for (const [d, col] of lane.cols) bandRows[Math.floor(d / perBand)] = Math.max(bandRows[Math.floor(d / perBand)], col.length);
      const bandTops = [];
      let at = inner;
      for (let b = 0; b < bands; b++) {
        bandTops.push(at);
        if (bandRows[b]) at += bandRows[b] * (BOX_H + ROW_GAP) - ROW_GAP + BAND_GAP;
      }
      for (const [d, col] of lane.cols) {
        const bandTop = bandTops[Math.floor(d / perBand)];
        col.forEach((n, i) => pos.set(n, { x: MARGIN + LANE_PAD + (d % perBand) * (BOX_W + COL_GAP), y: bandTop + i * (BOX_H + ROW_GAP), bandTop }));
      }
      const h = at - inner + LANE_HEAD - BAND_GAP + LANE_PAD;
      lanesOut.push({ app: lane.app, y: top, h });
      y = top + h + 10;
    }
    // Ports along the box's sides, ordered by where their other ends are: one anchor per port.
    const anchors = new Map();
    const spread = (name, side, list) => {
      const ports = [...new Set(list.sort((a, b) => a.other - b.other).map((x) => x.port))];
      ports.forEach((port, i) => anchors.set(name + "\u0000" + side + "\u0000" + port, pos.get(name).y + BOX_H * (i + 1) / (ports.length + 1)));
    };
    for (const n of names) {
      spread(n, "out", es.filter((e) => e.from === n).map((e) => ({ port: e.fromPort, other: pos.get(e.to).y })));
      spread(n, "in", es.filter((e) => e.to === n).map((e) => ({ port: e.toPort, other: pos.get(e.from).y })));
    }
    const anchor = (name, side, port) => anchors.get(name + "\u0000" + side + "\u0000" + port);
    const width = MARGIN * 2 + LANE_PAD * 2 + Math.min(maxDepth + 1, perBand) * (BOX_W + COL_GAP) - COL_GAP;
    return { pos, anchor, lanes: lanesOut, edges: es, width, height: y - 10 + MARGIN, boxes: new Map() };
  }

  function drawGraph() {
    const g = $("graph");
    const cs = components();
    $("graph-empty").hidden = cs.length > 0;
    if (!cs.length) { g.replaceChildren(); g.setAttribute("width", 0); g.setAttribute("height", 0); layout = null; return; }
    const focused = document.activeElement && document.activeElement.closest && document.activeElement.closest("#graph .box");
    const refocus = focused ? focused.getAttribute("data-component") : null;
    layout = computeLayout();
    const wrapW = $("graph-wrap").clientWidth - 2;
    const W = Math.max(layout.width, wrapW), H = layout.height;
    g.setAttribute("width", W); g.setAttribute("height", H); g.setAttribute("viewBox", `0 0 ${W} ${H}`);
    const defs = svg("defs", {},
      svg("marker", { id: "arrow", viewBox: "0 0 10 10", refX: "9", refY: "5", markerWidth: "7", markerHeight: "7", orient: "auto-start-reverse" },
        svg("path", { d: "M0,0 L10,5 L0,10 z", fill: "#8b96a1" })),
      svg("marker", { id: "arrow-hot", viewBox: "0 0 10 10", refX: "9", refY: "5", markerWidth: "7", markerHeight: "7", orient: "auto-start-reverse" },
        svg("path", { d: "M0,0 L10,5 L0,10 z", fill: "#1a5fb4" })));
    const lanesG = svg("g", {});
    const showLaneLabels = layout.lanes.length > 1 || (layout.lanes[0] && layout.lanes[0].app);
    for (const l of layout.lanes) {
      lanesG.append(svg("rect", { class: "lane-bg", x: MARGIN / 2, y: l.y, width: W - MARGIN, height: l.h, rx: 5 }));
      if (showLaneLabels) lanesG.append(svg("text", { class: "lane-label", x: MARGIN + 4, y: l.y + 15, text: (l.app || "top level").toUpperCase() }));
    }
    const edgesG = svg("g", {});
    // Port names only at the selected component's own sides (all of them: in the tooltips).
    const labelled = new Set();
    const portLabel = (key, attrs) => { if (!labelled.has(key)) { labelled.add(key); edgesG.append(svg("text", attrs)); } };
    for (const e of layout.edges) {
      const a = layout.pos.get(e.from), b = layout.pos.get(e.to);
      if (!a || !b) continue;
      const x1 = a.x + BOX_W, y1 = layout.anchor(e.from, "out", e.fromPort), x2 = b.x - 2, y2 = layout.anchor(e.to, "in", e.toPort);
      let d;
      if (x2 > x1 + 10) {
        const mx = (x1 + x2) / 2;
        d = `M${x1},${y1} C${mx},${y1} ${mx},${y2} ${x2},${y2}`;
      } else if (b.bandTop > a.bandTop) {
        // On to the next band: down through the gap above it, then in from the left.
        const gap = b.bandTop - BAND_GAP / 2;
        d = `M${x1},${y1} C${x1 + 40},${y1} ${x1 + 40},${gap} ${x1},${gap} L${x2 - 10},${gap} C${x2 - 40},${gap} ${x2 - 40},${y2} ${x2},${y2}`;
      } else {
        // Backwards or same column: around, under the boxes.
        const low = Math.max(a.y, b.y) + BOX_H + ROW_GAP / 2 + 2;
        d = `M${x1},${y1} C${x1 + 50},${y1} ${x1 + 50},${low} ${x1},${low} L${x2 + 10},${low} C${x2 - 40},${low} ${x2 - 40},${y2} ${x2},${y2}`;
      }
      const p = svg("path", { class: "edge" + (model.selected && (e.from === model.selected || e.to === model.selected) ? " hot" : ""), d, "marker-end": "url(#arrow)", "data-from": e.from, "data-to": e.to },
        svg("title", { text: `${e.from}.${e.fromPort} → ${e.to}.${e.toPort}` }));
      edgesG.append(p);
      if (e.from === model.selected) portLabel("out\u0000" + e.fromPort, { class: "edge-label", x: x1 + 5, y: y1 - 4, text: e.fromPort });
      if (e.to === model.selected) portLabel("in\u0000" + e.toPort, { class: "edge-label", x: x2 - 8, y: y2 - 4, "text-anchor": "end", text: e.toPort });
    }
    const boxesG = svg("g", {});
    for (const c of cs) {
      const p = layout.pos.get(c.name);
      const box = svg("g", { class: "box", transform: `translate(${p.x},${p.y})`, tabindex: "0", role: "button" });
      box.append(
        svg("title", {}),
        svg("rect", { class: "body", width: BOX_W, height: BOX_H, rx: 5 }),
        svg("rect", { class: "stripe", width: 6, height: BOX_H - 2, x: 1, y: 1, rx: 2 }),
        svg("text", { class: "name", x: 14, y: 23 }),
        svg("text", { class: "sub", x: 14, y: 44 }),
        svg("g", { class: "badge", transform: `translate(${BOX_W - 2},2)` }, svg("circle", { r: 10 }), svg("text", { y: 3.5 })));
      box.addEventListener("click", () => select(c.name));
      box.addEventListener("keydown", (ev) => { if (ev.key === "Enter" || ev.key === " ") { ev.preventDefault(); select(c.name); } });
      boxesG.append(box);
      layout.boxes.set(c.name, box);
    }
    g.replaceChildren(defs, lanesG, edgesG, boxesG);
    for (const c of cs) {
      // Fit the name in the box (full name in the tooltip and the details).
      const t = layout.boxes.get(c.name).querySelector("text.name");
      t.textContent = c.name;
      if (t.getComputedTextLength && t.getComputedTextLength() > BOX_W - 24) {
        let s = c.name;
        while (s.length > 4 && t.getComputedTextLength() > BOX_W - 24) { s = s.slice(1); t.textContent = "…" + s; }
      }
    }
    updateGraph();
    if (refocus && layout.boxes.has(refocus)) layout.boxes.get(refocus).focus();
  }

  function updateGraph() {
    if (!layout) return;
    for (const c of components()) {
      const box = layout.boxes.get(c.name);
      if (!box) continue;
      const state = String(c.state ?? "unknown");
      const faults = typeof c.faults === "number" ? c.faults : 0;
      const [fill, stroke, ink] = stateColours(state);
      box.setAttribute("data-component", c.name);
      box.setAttribute("data-state", state);
      box.setAttribute("data-faults", String(faults));
      box.classList.toggle("selected", model.selected === c.name);
      const label = `${c.name}: ${state}, ${plural(faults, "fault")}` + (c.pid ? `, pid ${c.pid}` : "");
      box.setAttribute("aria-label", label);
      box.querySelector("title").textContent = label + (c.application ? ` (application ${c.application})` : "");
      const body = box.querySelector("rect.body");
      body.setAttribute("fill", fill); body.setAttribute("stroke", stroke);
      box.querySelector("rect.stripe").setAttribute("fill", stroke);
      const sub = box.querySelector("text.sub");
      sub.setAttribute("fill", ink);
      sub.textContent = `${state} · ${plural(faults, "fault")}` + (c.pid ? ` · pid ${c.pid}` : "");
      const badge = box.querySelector(".badge");
      badge.setAttribute("visibility", faults > 0 ? "visible" : "hidden");
      badge.querySelector("text").textContent = faults > 99 ? "99+" : String(faults);
    }
    for (const p of $("graph").querySelectorAll("path.edge")) {
      const hot = model.selected && (p.dataset.from === model.selected || p.dataset.to === model.selected);
      p.classList.toggle("hot", !!hot);
      p.setAttribute("marker-end", hot ? "url(#arrow-hot)" : "url(#arrow)");
    }
  }

  function drawLegend() {
    const lg = $("legend");
    for (const s of ["Active", "Ready", "Created", "Error", "Stopped", "Destroyed"]) {
      const [f, c] = stateColours(s);
      const span = el("span", { text: s });
      span.style.setProperty("--f", f); span.style.setProperty("--c", c);
      lg.append(span);
    }
  }

  function select(name) {
    model.selected = model.selected === name ? null : name;
    invalidate("layout"); invalidate("counts"); invalidate("details");
  }

  // ---------------------------------------------------------------- counts table
  function statePill(state) {
    const [f, c, t] = stateColours(state);
    const s = el("span", { class: "state-pill", text: state });
    s.style.setProperty("--f", f); s.style.setProperty("--c", c); s.style.setProperty("--t", t);
    return s;
  }
  let countsKey = "";
  function drawCounts() {
    const body = $("counts").tBodies[0];
    const cs = components().slice();
    const key = JSON.stringify([model.selected, cs.map((c) => [c.name, c.application, c.state, c.faults])]);
    if (key === countsKey) return;
    countsKey = key;
    if (!cs.length) { body.replaceChildren(el("tr", { class: "empty-row" }, el("td", { colspan: 3, text: "No components yet." }))); return; }
    const order = new Map(cs.map((c, i) => [c.name, i]));
    cs.sort((a, b) => ((b.faults || 0) - (a.faults || 0)) || (order.get(a.name) - order.get(b.name)));
    let total = 0;
    body.replaceChildren(...cs.map((c) => {
      const n = typeof c.faults === "number" ? c.faults : 0;
      total += n;
      const tr = el("tr", { "data-row-component": c.name, class: model.selected === c.name ? "selected" : "", tabindex: "0" },
        el("td", { class: "mono", text: c.name, title: c.application ? "application " + c.application : null }),
        el("td", {}, statePill(String(c.state ?? "unknown"))),
        el("td", { class: "num faults" + (n ? " nonzero" : ""), text: String(n) }));
      tr.addEventListener("click", () => select(c.name));
      tr.addEventListener("keydown", (ev) => { if (ev.key === "Enter") select(c.name); });
      return tr;
    }));
    $("counts-total").textContent = `${plural(cs.length, "component")} · ${plural(total, "fault")}`;
  }

  // ---------------------------------------------------------------- details + ports
  function portsOf(name) {
    const prefix = "/keel/ports/" + name + "/";
    const out = [];
    for (const c of conn.channels.values()) {
      if (c.topic.startsWith(prefix) && !c.topic.slice(prefix.length).includes("/")) out.push({ port: c.topic.slice(prefix.length), topic: c.topic });
    }
    return out.sort((a, b) => a.port.localeCompare(b.port));
  }
  function toggleWatch(component, port, topic) {
    if (watched.has(topic)) {
      watched.delete(topic);
      unsubscribe(topic);
    } else {
      watched.set(topic, { component, port, value: undefined, t: null, count: 0, gone: false });
      const ch = channelByTopic(topic);
      if (ch) subscribe(ch);
    }
    invalidate("details");
  }
  let detailsKey = "";
  function drawDetails() {
    const d = $("details");
    const c = components().find((x) => x.name === model.selected);
    const key = JSON.stringify([c || null, c ? portsOf(c.name) : [], [...watched.keys()], c ? edges().filter((e) => e.from === c.name || e.to === c.name) : []]);
    if (key === detailsKey) return;
    detailsKey = key;
    const parts = [];
    if (!c) {
      parts.push(el("p", { class: "muted", text: components().length ? "Select a component in the graph or the table to see its state and ports." : "No component selected." }));
    } else {
      const es = edges();
      const ins = es.filter((e) => e.to === c.name).map((e) => `${e.toPort} ← ${e.from}.${e.fromPort}`);
      const outs = es.filter((e) => e.from === c.name).map((e) => `${e.fromPort} → ${e.to}.${e.toPort}`);
      const faults = typeof c.faults === "number" ? c.faults : 0;
      parts.push(el("div", { class: "who" },
        el("span", { class: "who-name", text: c.name }), statePill(String(c.state ?? "unknown")),
        el("span", { class: faults ? "who-faults nonzero" : "who-faults", text: plural(faults, "fault") })));
      const facts = [c.application ? "application " + c.application : "", c.pid ? "own process, pid " + c.pid : ""].filter(Boolean);
      if (facts.length) parts.push(el("div", { class: "muted", text: facts.join(" · ") }));
      parts.push(el("h3", { text: "Output ports — live values on demand" }));
      const ports = portsOf(c.name);
      if (!ports.length) parts.push(el("p", { class: "muted", text: "keel advertises no port channel for this component." }));
      else parts.push(el("ul", { class: "ports" }, ...ports.map((p) => portItem(c.name, p.port, p.topic, true))));
      if (ins.length || outs.length) {
        parts.push(el("h3", { text: "Connections" }));
        parts.push(el("ul", { class: "links" }, ...outs.map((t) => el("li", { text: t })), ...ins.map((t) => el("li", { text: t }))));
      }
    }
    const others = [...watched.entries()].filter(([, w]) => !c || w.component !== c.name);
    if (others.length) {
      parts.push(el("h3", { text: "Watched ports of other components" }));
      parts.push(el("ul", { class: "ports" }, ...others.map(([topic, w]) => portItem(w.component, w.port, topic, false))));
    }
    d.replaceChildren(...parts);
  }
  function portItem(component, port, topic, own) {
    const on = watched.has(topic);
    const btn = el("button", { type: "button", class: "small-btn", "aria-pressed": on ? "true" : "false", "data-topic": topic,
      text: on ? "Hide" : "Show value", title: (on ? "Unsubscribe from " : "Subscribe to ") + topic });
    btn.addEventListener("click", () => toggleWatch(component, port, topic));
    const li = el("li", { "data-port-topic": topic },
      el("span", { class: "port-name", text: own ? port : component + "/" + port, title: topic }), btn);
    if (on) li.append(el("div", { class: "port-value", "data-value-for": topic }));
    return li;
  }
  function drawPortValues() {
    for (const box of document.querySelectorAll("[data-value-for]")) {
      const w = watched.get(box.dataset.valueFor);
      if (!w) continue;
      const parts = [];
      if (w.t !== null) parts.push(el("span", { class: "age", text: "t " + fmtRunTime(w.t) }));
      parts.push(w.gone ? "channel no longer advertised" : w.count ? shortJson(w.value, 400) : "waiting for a value…");
      box.replaceChildren(...parts);
    }
  }

  // ---------------------------------------------------------------- timeline
  const rows = new Map();  // fault id -> tr
  function drawTimeline() {
    const body = $("timeline-body");
    for (const id of dropRows.splice(0)) { const r = rows.get(id); if (r) { r.remove(); rows.delete(id); } }
    for (const id of dirtyFaults) {
      const f = model.faults.get(id);
      if (!f) continue;
      let tr = rows.get(id);
      if (!tr) {
        tr = el("tr", { class: "fault", "data-fault-id": id });
        rows.set(id, tr);
        body.insertBefore(tr, body.firstChild);
        if (f.fresh && !document.hidden && !$("faults-view").hidden) tr.classList.add("fresh");
        f.fresh = false;
      }
      fillRow(tr, f);
    }
    dirtyFaults.clear();
    $("timeline-empty").hidden = rows.size > 0;
    $("faults-count").textContent = rows.size ? "(" + rows.size + ")" : "";
    if (rows.size) body.append($("timeline-empty"));
  }
  function fillRow(tr, f) {
    const v = faultView(f);
    const d = f.detected;
    if (v.detectionUs !== null) tr.setAttribute("data-detection-us", v.detectionUs.toFixed(3)); else tr.removeAttribute("data-detection-us");
    if (v.recoveryUs !== null) tr.setAttribute("data-recovery-us", v.recoveryUs.toFixed(3)); else tr.removeAttribute("data-recovery-us");
    tr.setAttribute("data-fault-component", f.component);
    if (v.injectedKind) tr.setAttribute("data-injected-kind", v.injectedKind);
    if (v.kind) tr.setAttribute("data-kind", v.kind);
    tr.setAttribute("data-outcome", v.outcome);
    const t = d && typeof d.t_ns === "number" ? d.t_ns : f.firstT;
    const kindCell = el("td", { title: v.injectedKind && v.injectedKind !== v.kind ? "injected as " + v.injectedKind : null }, v.kind || "—");
    if (v.injectedKind && v.kind && v.injectedKind !== v.kind) kindCell.append(el("div", { class: "muted", text: "inj. " + v.injectedKind }));
    const detailText = d ? d.detail || "" : f.notDetected ? "never detected" : f.injected && f.injected.detail ? f.injected.detail : "";
    const detail = el("td", { class: "detail", title: [d && d.detector, detailText].filter(Boolean).join(": ") || null });
    if (d && d.detector) detail.append(el("span", { class: "detector", text: d.detector }), detailText ? " · " : "");
    detail.append(el("span", { class: "text", text: detailText || (d ? "" : "—") }));
    const lat = (us, what) => el("td", { class: "num" + (us === null ? " lat-none" : ""), title: us === null ? "no " + what + " latency (yet)" : null, text: fmtLatency(us) });
    tr.replaceChildren(
      el("td", { class: "num mono", text: f.id }),
      el("td", { class: "num", text: fmtRunTime(t) }),
      el("td", { class: "mono", text: f.component || "—", title: f.component }),
      kindCell, detail,
      el("td", {}, stepsOf(f)),
      lat(v.detectionUs, "detection"), lat(v.recoveryUs, "recovery"),
      el("td", {}, el("span", { class: "outcome " + v.outcome.replace(/ /g, "-"), text: v.outcome })));
  }
  function stepsOf(f) {
    const steps = [];
    const base = f.detected && typeof f.detected.t_ns === "number" ? f.detected.t_ns : null;
    const at = (r) => typeof r.t_ns === "number" ? "t " + fmtRunTime(r.t_ns) + (base !== null && r !== f.detected ? ` (${r.t_ns >= base ? "+" : "−"}${fmtLatency(Math.abs(r.t_ns - base) / 1000)})` : "") : "";
    const step = (cls, text, r, extra) => steps.push(el("span", { class: "step " + cls, text, title: [at(r), extra].filter(Boolean).join(" · ") || null }));
    if (f.injected) step("injected", f.injected.hardware ? "hardware: " + (f.injected.kind || "") : "injected", f.injected, f.injected.detail);
    if (f.detected) step("detected", "detected", f.detected, f.detected.detector);
    if (f.diagnosed) {
      const dg = f.diagnosed;
      const text = dg.severity && dg.handling && dg.severity !== dg.handling ? `${dg.severity} → ${dg.handling}` : dg.handling || dg.severity || "diagnosed";
      step("diagnosed", "diagnosed: " + text, dg, [dg.rules, dg.scope && "scope " + dg.scope].filter(Boolean).join(", "));
    }
    for (const a of f.actions) step("action" + (a.outcome === "failed" ? " failed" : ""), `${a.action || "action"}: ${a.outcome || "?"}`, a, a.detail || a.replacement);
    if (f.recovered) step("recovered", "recovered", f.recovered);
    const wrap = el("div", { class: "steps" });
    steps.forEach((s, i) => { if (i) wrap.append(el("span", { class: "arrow", text: "→", "aria-hidden": "true" })); wrap.append(s); });
    if (!steps.length) wrap.append(el("span", { class: "muted", text: f.armed ? "armed" : "—" }));
    return wrap;
  }

  // ---------------------------------------------------------------- events
  function eventText(r) {
    switch (r.event) {
      case "engine": {
        const bits = [r.phase];
        if (r.phase === "load") bits.push(`${r.name || ""} · ${r.instances ?? (r.components || []).length} instances`);
        if (r.phase === "started" && r.executors !== undefined) bits.push(plural(r.executors, "executor"));
        if (r.reason) bits.push(r.reason);
        return bits.filter(Boolean).join(" · ");
      }
      case "emergency": return `${r.phase}${r.by ? " by " + r.by : ""}`;
      case "warning": return r.message || shortJson(r, 200);
      case "host": return `${r.process || "?"} (pid ${r.pid ?? "?"}) ${r.phase || ""}${r.detail ? ": " + r.detail : ""}`;
      case "action": return `${r.action || "?"}: ${r.outcome || "?"}${r.by ? " by " + r.by : ""}${r.detail ? " · " + r.detail : ""}` +
        (typeof r.latency_us === "number" ? " · " + fmtLatency(r.latency_us) : "");
      case "state": return `application ${r.application} ${r.from || "?"} → ${r.to || "?"}${r.fault_id !== undefined ? " (fault " + r.fault_id + ")" : ""}`;
      case "end_requested": return `${r.component || "?"}: ${r.summary || ""}`;
      default: { const { event, t_ns, ...rest } = r; return shortJson(rest, 240); }
    }
  }
  function drawEvents() {
    $("events-count").textContent = model.events.length ? "(" + model.events.length + ")" : "";
    $("events").replaceChildren(...model.events.map((r) => el("li", {
      "data-event": r.event, "data-bad": r.event === "host" && (r.phase === "died" || r.phase === "failed") ? "true" : null },
      el("span", { class: "num muted", text: fmtRunTime(r.t_ns) }),
      el("span", { class: "ev", text: r.event }),
      el("span", { class: "what", text: eventText(r) }))));
    if (!model.events.length) $("events").append(el("li", { class: "empty muted", text: "No run event since this page connected." }));
  }

  // ---------------------------------------------------------------- header, status
  function drawHeader() {
    $("run-name").textContent = model.runName || "—";
    $("run-name").title = (model.serverInfo && model.serverInfo.metadata && model.serverInfo.metadata.profile) || "";
    document.title = (model.emergency ? "⛔ " : "") + (model.runName ? model.runName + " — " : "") + "keel monitor";
    const e = $("emergency");
    e.textContent = model.emergency === null ? "unknown" : model.emergency ? "latched" : "not latched";
    e.dataset.latched = model.emergency === null ? "unknown" : String(model.emergency);
    $("top").classList.toggle("latched", model.emergency === true);
    $("clock").textContent = fmtRunTime(model.lastT);
  }
  function drawStatus() {
    $("status-messages").replaceChildren(...statuses.map((s) => {
      const x = el("button", { type: "button", "aria-label": "dismiss", title: "dismiss", text: "×" });
      x.addEventListener("click", () => { const i = statuses.indexOf(s); if (i >= 0) statuses.splice(i, 1); invalidate("status"); });
      return el("li", { "data-level": String(s.level), title: "at " + s.at.toLocaleTimeString() },
        (s.level === 2 ? "error: " : s.level === 1 ? "warning: " : "") + s.message, x);
    }));
  }

  // ---------------------------------------------------------------- render
  function render() {
    const has = (k) => dirty.has(k);
    if (has("layout")) drawGraph(); else if (has("graph")) updateGraph();
    if (has("counts")) drawCounts();
    if (has("details")) drawDetails();
    if (has("details") || has("ports")) drawPortValues();
    if (has("timeline")) drawTimeline();
    if (has("events")) drawEvents();
    if (has("header")) drawHeader();
    if (has("status")) drawStatus();
    dirty.clear();
  }
  let lastWidth = 0;
  new ResizeObserver(() => {
    const w = $("graph-wrap").clientWidth;
    if (w !== lastWidth) { lastWidth = w; if (model.state) invalidate("layout"); }
  }).observe($("graph-wrap"));

  function showTab(tab) {
    for (const [t, view] of [["tab-faults", "faults-view"], ["tab-events", "events-view"]]) {
      const on = t === tab;
      $(t).setAttribute("aria-selected", String(on));
      $(t).tabIndex = on ? 0 : -1;
      $(view).hidden = !on;
    }
    $("timeline-hint").hidden = tab !== "tab-faults";
    // Rows that arrived while hidden are not news when shown.
    for (const r of document.querySelectorAll("#timeline tr.fresh")) r.classList.remove("fresh");
  }
  for (const t of ["tab-faults", "tab-events"]) {
    $(t).addEventListener("click", () => showTab(t));
    $(t).addEventListener("keydown", (ev) => {
      if (ev.key !== "ArrowLeft" && ev.key !== "ArrowRight") return;
      const other = t === "tab-faults" ? "tab-events" : "tab-faults";
      showTab(other);
      $(other).focus();
    });
  }

  drawLegend();
  drawEvents();
  updateControls();
  connect();
})();
