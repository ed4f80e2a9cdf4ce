// hal-web's page: the HAL tree with live values, a watch list and meters
// kept in localStorage, changes through halcmd's commands, and the
// machine panel (the scope and the threads are in scope.js and
// threads.js).
// Every API request carries the access token (when one is in force) in
// the X-HAL-Token header, never in a URL.
"use strict";

const state = {
  token: sessionStorage.getItem("hal-web.token") || "",
  show: null,
  rows: new Map(),      // "kind:name" -> value cells
  streamKeys: [],
  streamAbort: null,
  instance: "",
};

const $ = (id) => document.getElementById(id);

function say(text, isError) {
  const m = $("message");
  m.textContent = text;
  m.className = isError ? "error" : "";
}

async function api(path, body, accept) {
  const init = { method: body === undefined ? "GET" : "POST", headers: {} };
  if (accept) init.headers["Accept"] = accept;
  if (state.token) init.headers["X-HAL-Token"] = state.token;
  if (body !== undefined) {
    init.headers["Content-Type"] = "application/json";
    init.body = JSON.stringify(body);
  }
  const r = await fetch(path, init);
  if (r.status === 401) $("token-form").hidden = false;
  return r;
}

async function answer(r) {
  let j = {};
  try { j = await r.json(); } catch (e) { j = { error: r.statusText }; }
  return j;
}

// ---- watch list (per instance, in localStorage) ----

function watchKey() { return "hal-web.watch." + state.instance; }

function watched() {
  try { return JSON.parse(localStorage.getItem(watchKey()) || "[]"); }
  catch (e) { return []; }
}

function setWatched(list) {
  localStorage.setItem(watchKey(), JSON.stringify(list));
  drawWatch();
  restartStream();
}

function toggleWatch(kind, name) {
  const list = watched();
  const i = list.findIndex((w) => w.kind === kind && w.name === name);
  if (i >= 0) list.splice(i, 1); else list.push({ kind, name });
  setWatched(list);
}

// ---- meters (per instance, in localStorage): value, min and max ----

function metersKey() { return "hal-web.meters." + state.instance; }

function meterList() {
  try { return JSON.parse(localStorage.getItem(metersKey()) || "[]"); }
  catch (e) { return []; }
}

function toggleMeter(kind, name) {
  const list = meterList();
  const i = list.findIndex((m) => m.kind === kind && m.name === name);
  if (i >= 0) list.splice(i, 1); else if (list.length < 16) list.push({ kind, name });
  else say("a page shows at most 16 meters", true);
  localStorage.setItem(metersKey(), JSON.stringify(list));
  drawMeters();
  restartStream();
}

function drawMeters() {
  const body = $("meters").tBodies[0];
  body.textContent = "";
  for (const m of meterList()) {
    const tr = document.createElement("tr");
    tr.dataset.kind = m.kind;
    tr.dataset.name = m.name;
    tr.appendChild(cell(m.name));
    tr.appendChild(cell("…", "value"));
    tr.appendChild(cell("", "min"));
    tr.appendChild(cell("", "max"));
    const td = document.createElement("td");
    const b = document.createElement("button");
    b.type = "button";
    b.textContent = "remove";
    b.addEventListener("click", () => toggleMeter(m.kind, m.name));
    td.appendChild(b);
    tr.appendChild(td);
    body.appendChild(tr);
  }
}

function applyMeters(meters) {
  const rows = $("meters").tBodies[0].rows;
  const num = (x) => (x === null || x === undefined ? "" : String(x));
  for (const [i, m] of Object.entries(meters)) {
    const tr = rows[Number(i)];
    if (!tr) continue;
    tr.querySelector(".value").textContent = m.value === null ? "(gone)" : m.value;
    tr.querySelector(".min").textContent = num(m.min);
    tr.querySelector(".max").textContent = num(m.max);
  }
}

// ---- rows ----

function cell(text, cls) {
  const td = document.createElement("td");
  td.textContent = text === null || text === undefined ? "" : String(text);
  if (cls) td.className = cls;
  return td;
}

function valueCell(kind, name, value) {
  const td = cell(value, "value");
  const key = kind + ":" + name;
  if (!state.rows.has(key)) state.rows.set(key, []);
  state.rows.get(key).push(td);
  return td;
}

// A setp/sets field for what halcmd may set.
function setField(kind, name) {
  const td = document.createElement("td");
  const command = kind === "sig" ? "sets" : "setp";
  const input = document.createElement("input");
  input.className = "set";
  input.placeholder = command;
  input.setAttribute("aria-label", command + " " + name);
  input.addEventListener("keydown", async (e) => {
    if (e.key !== "Enter") return;
    await change(command, [name, input.value]);
  });
  td.appendChild(input);
  return td;
}

function watchButton(kind, name) {
  const td = document.createElement("td");
  const b = document.createElement("button");
  b.className = "watch";
  b.type = "button";
  b.textContent = "watch";
  b.addEventListener("click", () => toggleWatch(kind, name));
  td.appendChild(b);
  return td;
}

function meterButton(kind, name) {
  const td = document.createElement("td");
  const b = document.createElement("button");
  b.className = "meter";
  b.type = "button";
  b.textContent = "meter";
  b.addEventListener("click", () => toggleMeter(kind, name));
  td.appendChild(b);
  return td;
}

function rowFor(kind, o) {
  const tr = document.createElement("tr");
  tr.dataset.kind = kind;
  tr.dataset.name = o.name;
  tr.appendChild(cell(o.name));
  tr.appendChild(cell(o.type || "", "row-kind"));
  tr.appendChild(cell(o.dir || "", "row-kind"));
  if (kind === "thread" || kind === "funct") {
    tr.appendChild(valueCell(kind, o.name, o.time + " ns (max " + o.tmax + " ns)"));
  } else {
    tr.appendChild(valueCell(kind, o.name, o.value));
  }
  let extra = "";
  if (kind === "pin" && o.signal) extra = (o.dir === "IN" ? "<== " : "==> ") + o.signal;
  if (kind === "sig") {
    extra = "writer: " + (o.writer || "none") + "; readers: " + (o.readers.join(" ") || "none");
    if (o.bidirs.length) extra += "; I/O: " + o.bidirs.join(" ");
  }
  if (kind === "thread") extra = (o.running ? "running" : "stopped") + ": " + o.functs.join(" ");
  tr.appendChild(cell(extra, "row-kind"));
  const settable = (kind === "pin" && o.dir !== "OUT" && !o.signal) ||
    (kind === "param" && o.dir === "RW") || (kind === "sig" && !o.writer);
  tr.appendChild(settable ? setField(kind, o.name) : cell(""));
  tr.appendChild(watchButton(kind, o.name));
  tr.appendChild(kind === "pin" || kind === "sig" || kind === "param"
    ? meterButton(kind, o.name) : cell(""));
  return tr;
}

// ---- the tree ----

const GROUPS = [
  ["pins", "pin", "Pins"], ["params", "param", "Parameters"], ["signals", "sig", "Signals"],
  ["functs", "funct", "Functions"], ["threads", "thread", "Threads"],
];

function drawTree() {
  const tree = $("tree");
  tree.textContent = "";
  state.rows.clear();
  if (!state.show) return;
  const filter = $("filter").value.trim().toLowerCase();
  for (const [field, kind, title] of GROUPS) {
    const items = state.show[field].filter((o) => o.name.toLowerCase().includes(filter));
    const group = document.createElement("details");
    group.dataset.kind = kind;
    const s = document.createElement("summary");
    s.textContent = title + " (" + items.length + ")";
    group.appendChild(s);
    // Objects under their first name part (the component, mostly).
    const byPrefix = new Map();
    for (const o of items) {
      const p = o.name.split(".")[0];
      if (!byPrefix.has(p)) byPrefix.set(p, []);
      byPrefix.get(p).push(o);
    }
    for (const [prefix, list] of byPrefix) {
      const sub = document.createElement("details");
      const ss = document.createElement("summary");
      ss.textContent = prefix + " (" + list.length + ")";
      sub.appendChild(ss);
      const table = document.createElement("table");
      const body = document.createElement("tbody");
      for (const o of list) body.appendChild(rowFor(kind, o));
      table.appendChild(body);
      sub.appendChild(table);
      sub.open = filter !== "" && items.length <= 200;
      sub.addEventListener("toggle", restartStream);
      group.appendChild(sub);
    }
    group.open = filter !== "";
    group.addEventListener("toggle", restartStream);
    tree.appendChild(group);
  }
  drawWatch();
  drawMeters();
  restartStream();
}

function drawWatch() {
  const body = $("watch").tBodies[0];
  body.textContent = "";
  for (const key of [...state.rows.keys()]) {
    state.rows.set(key, state.rows.get(key).filter((td) => !td.closest("#watch")));
  }
  for (const w of watched()) {
    const tr = document.createElement("tr");
    tr.dataset.kind = w.kind;
    tr.dataset.name = w.name;
    tr.appendChild(cell(w.kind, "row-kind"));
    tr.appendChild(cell(w.name));
    tr.appendChild(valueCell(w.kind, w.name, "…"));
    tr.appendChild(w.kind === "pin" || w.kind === "param" || w.kind === "sig"
      ? setField(w.kind, w.name) : cell(""));
    const td = document.createElement("td");
    const b = document.createElement("button");
    b.type = "button";
    b.textContent = "remove";
    b.addEventListener("click", () => toggleWatch(w.kind, w.name));
    td.appendChild(b);
    tr.appendChild(td);
    body.appendChild(tr);
  }
}

// ---- the live stream: watched items and the rows of open groups ----

function visibleItems() {
  const items = new Map();
  for (const w of watched()) items.set(w.kind + ":" + w.name, w);
  for (const tr of document.querySelectorAll("#tree tr")) {
    const sub = tr.closest("details");
    const group = sub && sub.parentElement.closest("details");
    if (sub && sub.open && group && group.open) {
      const w = { kind: tr.dataset.kind, name: tr.dataset.name };
      items.set(w.kind + ":" + w.name, w);
    }
  }
  return [...items.values()].slice(0, 2000);
}

let restartTimer = null;
function restartStream() {
  clearTimeout(restartTimer);
  restartTimer = setTimeout(startStream, 100);
}

async function startStream() {
  if (state.streamAbort) state.streamAbort.abort();
  const items = visibleItems();
  state.streamKeys = items.map((w) => w.kind + ":" + w.name);
  const meters = meterList();
  if (items.length === 0 && meters.length === 0) return;
  const abort = new AbortController();
  state.streamAbort = abort;
  const headers = { "Content-Type": "application/json" };
  if (state.token) headers["X-HAL-Token"] = state.token;
  let r;
  try {
    r = await fetch("/api/stream", {
      method: "POST", headers, signal: abort.signal,
      body: JSON.stringify({ items, meters, hz: 10 }),
    });
  } catch (e) { return; }
  if (!r.ok) { say("live values: " + (await answer(r)).error, true); return; }
  $("conn").textContent = "live";
  const reader = r.body.getReader();
  const decoder = new TextDecoder();
  let buf = "";
  const keys = state.streamKeys;
  try {
    for (;;) {
      const { value, done } = await reader.read();
      if (done) break;
      buf += decoder.decode(value, { stream: true });
      let end;
      while ((end = buf.indexOf("\n\n")) >= 0) {
        const event = buf.slice(0, end);
        buf = buf.slice(end + 2);
        for (const line of event.split("\n")) {
          if (line.startsWith("data:")) applyValues(keys, JSON.parse(line.slice(5)));
        }
      }
    }
  } catch (e) { /* aborted for a new stream */ }
  if (state.streamAbort === abort) $("conn").textContent = "stream ended";
}

function applyValues(keys, event) {
  if (event.meters) applyMeters(event.meters);
  for (const [i, v] of Object.entries(event.values || {})) {
    const cells = state.rows.get(keys[Number(i)]) || [];
    for (const td of cells) td.textContent = v === null ? "(gone)" : v;
  }
}

// ---- changes ----

async function change(command, args) {
  const r = await api("/api/hal", { command, args });
  const j = await answer(r);
  if (r.ok) say(command + " " + args.join(" ") + ": done" + (j.output ? "\n" + j.output : ""), false);
  else say(j.error || r.statusText, true);
}

// ---- the machine ----

const BUTTONS = [
  ["estop", "E-STOP"], ["estop-reset", "E-stop reset"], ["machine-on", "Machine on"],
  ["machine-off", "Machine off"], ["mode-manual", "Manual"], ["home", "Home all"],
  ["mode-auto", "Auto"], ["run", "Run"], ["pause", "Pause"], ["resume", "Resume"],
  ["abort", "Abort"],
];

function drawButtons() {
  const box = $("machine-buttons");
  for (const [action, label] of BUTTONS) {
    const b = document.createElement("button");
    b.type = "button";
    b.id = "machine-" + action;
    b.textContent = label;
    if (action === "estop") b.className = "estop";
    b.addEventListener("click", async () => {
      const r = await api("/api/machine", { action });
      const j = await answer(r);
      if (r.ok) say(label + ": " + (j.answer || "done"), false);
      else say(label + ": " + (j.error || r.statusText), true);
      pollMachine();
    });
    box.appendChild(b);
  }
}

async function pollMachine() {
  let j;
  try {
    const r = await api("/api/machine");
    if (!r.ok) return;
    j = await r.json();
  } catch (e) { return; }
  const body = $("machine-state").tBodies[0];
  body.textContent = "";
  const add = (k, v) => {
    const tr = document.createElement("tr");
    tr.appendChild(cell(k));
    tr.appendChild(cell(v));
    tr.dataset.key = k;
    body.appendChild(tr);
  };
  if (!j.running) add("machine", "no machine (" + j.error + ")");
  for (const [k, v] of Object.entries(j.state || {})) add(k, v);
  const m = j.motion || {};
  for (const [n, jt] of Object.entries(m.joints || {})) {
    add("joint " + n, (jt["pos-fb"] || "") + (jt.homed === "TRUE" ? " homed" : ""));
  }
  for (const [l, v] of Object.entries(m.axes || {})) add("axis " + l, v);
  if (m["program-line"] !== undefined && m["program-line"] !== null) add("line", m["program-line"]);
  $("machine-status").textContent = j.status || "";
}

// ---- start ----

async function load() {
  const r = await api("/api/show");
  if (!r.ok) {
    const j = await answer(r);
    $("conn").textContent = "not connected";
    say(j.error || r.statusText, true);
    return;
  }
  state.show = await r.json();
  state.instance = state.show.instance;
  $("instance").textContent = "— " + state.instance;
  $("conn").textContent = "connected";
  drawTree();
  scopeThreads();
}

document.addEventListener("DOMContentLoaded", () => {
  $("token-form").addEventListener("submit", (e) => {
    e.preventDefault();
    state.token = $("token").value.trim();
    sessionStorage.setItem("hal-web.token", state.token);
    $("token-form").hidden = true;
    load();
  });
  $("filter").addEventListener("input", () => drawTree());
  $("refresh").addEventListener("click", () => load());
  $("meters-reset").addEventListener("click", () => { drawMeters(); restartStream(); });
  $("change-form").addEventListener("submit", (e) => {
    e.preventDefault();
    const words = $("change-args").value.trim().split(/\s+/).filter((w) => w);
    change($("change-command").value, words);
  });
  drawButtons();
  load();
  setInterval(pollMachine, 1000);
  pollMachine();
});
