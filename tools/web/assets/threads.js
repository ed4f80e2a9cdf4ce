// hal-web's thread view: each thread's timing and wake-up latency figures
// (as latency-test reads them) and the latency histograms, once a second.
// Uses app.js's $, api and cell.
"use strict";

const THREAD_COLORS = ["#c00", "#00c", "#070", "#b0b", "#c70", "#077"];

function us(ns) { return ns === null || ns === undefined ? "-" : (ns / 1000).toFixed(1); }

function drawThreadTable(j) {
  const body = $("threads").tBodies[0];
  body.textContent = "";
  for (const t of j.threads) {
    const tr = document.createElement("tr");
    tr.dataset.name = t.name;
    const l = t.latency;
    for (const v of [t.name, t.period_text, t.time, t.tmax, t.cycles, t.overruns,
      us(l.min), us(l.p50), us(l.p99), us(l.p999), us(l.max)]) {
      tr.appendChild(cell(v));
    }
    body.appendChild(tr);
  }
  $("verdict").textContent = j.verdict ? "— " + j.verdict.sentence : "";
}

// Bars per bucket (log scale of the counts), one color per thread, side
// by side; bucket edges in µs under the axis.
function drawHistogram(j) {
  const canvas = $("latency");
  const g = canvas.getContext("2d");
  const w = canvas.width, h = canvas.height, base = h - 16;
  g.fillStyle = "#fff";
  g.fillRect(0, 0, w, h);
  const floors = j.bucket_floor_us;
  let used = 0;
  for (const t of j.threads) {
    t.histogram.forEach((n, b) => { if (n > 0) used = Math.max(used, b + 1); });
  }
  if (used === 0) { canvas.dataset.bars = "0"; return; }
  const top = Math.max(...j.threads.flatMap((t) => t.histogram.slice(0, used)));
  const slot = w / used;
  const bar = slot / Math.max(1, j.threads.length);
  let bars = 0;
  j.threads.forEach((t, k) => {
    g.fillStyle = THREAD_COLORS[k % THREAD_COLORS.length];
    t.histogram.slice(0, used).forEach((n, b) => {
      if (n === 0) return;
      const height = (Math.log10(n + 1) / Math.log10(top + 1)) * (base - 14);
      g.fillRect(b * slot + k * bar, base - height, Math.max(1, bar - 1), height);
      bars++;
    });
    g.fillText(t.name, 6 + 110 * k, 12);
  });
  g.fillStyle = "#000";
  g.font = "10px sans-serif";
  for (let b = 0; b < used; b += Math.ceil(used / 16)) g.fillText(floors[b] + "us", b * slot, h - 3);
  canvas.dataset.bars = String(bars);
}

async function pollThreads() {
  let j;
  try {
    const r = await api("/api/threads");
    if (!r.ok) return;
    j = await r.json();
  } catch (e) { return; }
  drawThreadTable(j);
  drawHistogram(j);
}

document.addEventListener("DOMContentLoaded", () => {
  pollThreads();
  setInterval(pollThreads, 1000);
});
