// hal-web's scope: asks the server for a capture in halscope's words (its
// sampler and trigger take it), draws the record on a canvas, and saves
// it as halscope's CSV (served by hal-web) or as a PNG of the canvas.
// Uses app.js's state, $, api, answer and say.
"use strict";

const scope = { running: false, record: null };

const SCOPE_COLORS = ["#d00", "#070", "#00c", "#b0b", "#c70", "#077", "#555", "#770"];
const DIVISIONS_X = 10;
const DIVISIONS_Y = 8;

function scopePins() {
  return $("scope-pins").value.split(",").map((p) => p.trim()).filter((p) => p);
}

// The trigger's choices follow the channels.
function scopeTriggerChoices() {
  const select = $("scope-trigger");
  const was = select.value;
  select.textContent = "";
  for (const name of ["", ...scopePins()]) {
    const o = document.createElement("option");
    o.value = name;
    o.textContent = name || "none (at once)";
    select.appendChild(o);
  }
  select.value = scopePins().includes(was) ? was : "";
}

function scopeThreads() {
  const select = $("scope-thread");
  const was = select.value;
  select.textContent = "";
  for (const t of (state.show && state.show.threads) || []) {
    const o = document.createElement("option");
    o.value = t.name;
    o.textContent = t.name + " (" + t.period / 1000 + " us)";
    o.dataset.period = t.period;
    select.appendChild(o);
  }
  if (was) select.value = was;
}

// The request: the time base (ms per division) and the thread's period
// give the record's length.
function scopeRequest() {
  const option = $("scope-thread").selectedOptions[0];
  const period = option ? Number(option.dataset.period) : 1e6;
  const ms = Number($("scope-timebase").value) || 1;
  const samples = Math.max(2, Math.min(200000, Math.round(DIVISIONS_X * ms * 1e6 / period)));
  const req = {
    pins: scopePins(), thread: option ? option.value : "", samples,
    pre: ($("scope-pre").value || "0") + "%", mode: $("scope-mode").value, timeout: 10,
  };
  const trig = $("scope-trigger").value;
  if (trig) req.trigger = trig + ":" + $("scope-edge").value + ":" + ($("scope-level").value || "0");
  return req;
}

// A record in hal-web's binary form (tools/web/src/record.rs): the
// header's length (u32), the header (JSON), zeros to a multiple of 8,
// then each channel's samples as f64, all little-endian.
function scopeDecode(buf) {
  const view = new DataView(buf);
  const len = view.getUint32(0, true);
  const rec = JSON.parse(new TextDecoder().decode(new Uint8Array(buf, 4, len)));
  let at = Math.ceil((4 + len) / 8) * 8;
  rec.columns = rec.names.map(() => {
    const col = new Array(rec.samples);
    for (let i = 0; i < rec.samples; i++, at += 8) col[i] = view.getFloat64(at, true);
    return col;
  });
  return rec;
}

async function scopeRun() {
  if (scope.running) return;
  scope.running = true;
  $("scope-state").textContent = "waiting";
  try {
    do {
      const r = await api("/api/scope", scopeRequest(), "application/octet-stream");
      if (!r.ok) {
        const j = await answer(r);
        // Normal and auto modes keep waiting for a trigger that is late.
        const late = r.status === 422 && /no complete record/.test(j.error || "");
        if (late && $("scope-mode").value !== "single") continue;
        say("scope: " + (j.error || r.statusText), true);
        break;
      }
      const rec = scopeDecode(await r.arrayBuffer());
      scope.record = rec;
      scopeDraw();
      $("scope-state").textContent = rec.triggered ? "triggered" : "untriggered (auto)";
    } while (scope.running && $("scope-mode").value !== "single");
  } finally {
    scope.running = false;
    if ($("scope-state").textContent === "waiting") $("scope-state").textContent = "stopped";
  }
}

function scopeGrid(g, w, h) {
  g.fillStyle = "#fff";
  g.fillRect(0, 0, w, h);
  g.strokeStyle = "#ddd";
  g.lineWidth = 1;
  for (let i = 0; i <= DIVISIONS_X; i++) {
    g.beginPath(); g.moveTo(i * w / DIVISIONS_X, 0); g.lineTo(i * w / DIVISIONS_X, h); g.stroke();
  }
  for (let i = 0; i <= DIVISIONS_Y; i++) {
    g.beginPath(); g.moveTo(0, i * h / DIVISIONS_Y); g.lineTo(w, i * h / DIVISIONS_Y); g.stroke();
  }
}

// Each channel on its own scale (its smallest to largest value, with a
// margin), the trigger as a vertical line, names and ranges on top.
function scopeDraw() {
  const rec = scope.record;
  const canvas = $("scope");
  const g = canvas.getContext("2d");
  const w = canvas.width, h = canvas.height;
  scopeGrid(g, w, h);
  if (!rec) return;
  const n = rec.columns.length ? rec.columns[0].length : 0;
  const x = (i) => (n > 1 ? i * (w - 1) / (n - 1) : 0);
  let drawn = 0;
  rec.columns.forEach((col, c) => {
    const finite = col.filter((v) => v !== null && isFinite(v));
    const lo = Math.min(...finite), hi = Math.max(...finite);
    const span = hi > lo ? hi - lo : 1;
    const y = (v) => h - 8 - ((v - lo) / span) * (h - 16) - (hi > lo ? 0 : (h - 16) / 2);
    g.strokeStyle = SCOPE_COLORS[c % SCOPE_COLORS.length];
    g.lineWidth = 1.5;
    g.beginPath();
    col.forEach((v, i) => {
      if (v === null || !isFinite(v)) return;
      if (i === 0) g.moveTo(x(i), y(v)); else g.lineTo(x(i), y(v));
      drawn++;
    });
    g.stroke();
    g.fillStyle = g.strokeStyle;
    g.font = "12px sans-serif";
    g.fillText(rec.names[c] + " [" + lo + " .. " + hi + "]", 6, 14 + 14 * c);
  });
  if (rec.triggered) {
    g.strokeStyle = "#000";
    g.setLineDash([4, 4]);
    g.beginPath(); g.moveTo(x(rec.trigger_index), 0); g.lineTo(x(rec.trigger_index), h); g.stroke();
    g.setLineDash([]);
  }
  const ms = rec.period_ns / 1e6;
  $("scope-info").textContent = n + " samples, " + ms + " ms apart; " +
    ((n * ms) / DIVISIONS_X).toPrecision(3) + " ms/div; trigger at sample " + rec.trigger_index;
  canvas.dataset.samples = String(n);
  canvas.dataset.drawn = String(drawn);
}

function scopeSave(href, name) {
  const a = $("scope-download");
  a.href = href;
  a.download = name;
  a.click();
}

async function scopeCsv() {
  const r = await api("/api/scope.csv");
  if (!r.ok) { say("scope CSV: " + ((await answer(r)).error || r.statusText), true); return; }
  const text = await r.text();
  $("scope-download").dataset.csvLines = String(text.split("\n").length - 1);
  scopeSave(URL.createObjectURL(new Blob([text], { type: "text/csv" })), "halscope.csv");
}

function scopePng() {
  const url = $("scope").toDataURL("image/png");
  $("scope-download").dataset.png = url.slice(0, 22);
  scopeSave(url, "halscope.png");
}

document.addEventListener("DOMContentLoaded", () => {
  $("scope-pins").addEventListener("input", scopeTriggerChoices);
  $("scope-form").addEventListener("submit", (e) => { e.preventDefault(); scopeRun(); });
  $("scope-stop").addEventListener("click", () => { scope.running = false; });
  $("scope-csv").addEventListener("click", scopeCsv);
  $("scope-png").addEventListener("click", scopePng);
  scopeTriggerChoices();
  scopeDraw();
});
