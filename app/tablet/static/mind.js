// The live view of the robot's mind: snapshots pushed by Server-Sent Events during a run
// (or a tablet session), or fetched at the slider's time in a replay.
"use strict";

function bar(name, value, range) {
  const v = Math.max(0, Math.min(1, value));
  const track = el("div", {class: "track"});
  if (range) {
    const inside = value >= range[0] && value <= range[1];
    const band = el("div", {class: "band"});
    band.style.left = `${range[0] * 100}%`;
    band.style.width = `${(range[1] - range[0]) * 100}%`;
    track.append(band);
    track.classList.add(inside ? "ok" : "out");
  }
  const fill = el("div", {class: "fill"});
  fill.style.width = `${v * 100}%`;
  track.append(fill);
  return el("div", {class: "bar", "data-name": name}, el("span", {class: "name"}, name),
    track, el("span", {class: "value"}, value.toFixed(2)));
}

function statusClass(line) {
  if (line.includes("✓")) return "success";
  if (line.includes("✕")) return "failure";
  if (line.includes("*")) return "running";
  return "idle";
}

function render(s) {
  const positive = s.mood ? s.mood.positive : true;
  document.getElementById("mouth").setAttribute("d",
    positive ? "M30 65 Q50 80 70 65" : "M30 75 Q50 60 70 75");
  document.getElementById("face").classList.toggle("sad", !positive);
  document.getElementById("mood-word").textContent = positive ? "positive" : "negative";
  document.getElementById("mood-value").textContent =
    s.mood ? "v = " + s.mood.value.toFixed(3) : "";
  document.getElementById("clock").textContent = "t = " + (s.t || 0).toFixed(1) + " s";
  document.getElementById("action").textContent = s.action || "–";
  const why = s.why || {};
  const parts = [];
  if (why.reason) parts.push(`why: ${why.reason}` + (why.since != null ? ` (since ${why.since} s)` : ""));
  if (why.preempted) parts.push(`pre-empted ${why.preempted.action} at ${why.preempted.t} s` +
    (why.preempted.reason ? ` (${why.preempted.reason})` : ""));
  if (why.credited) parts.push(`last feedback: ${why.credited.reward > 0 ? "+1" : "-1"} for ${why.credited.action}`);
  document.getElementById("why").textContent = parts.join(" · ");
  document.getElementById("answering").textContent =
    s.answering && s.answering.length ? "answering: " + s.answering.join(" | ") : "";
  const drives = document.getElementById("drives");
  drives.replaceChildren(...Object.entries(s.drives || {}).map(([k, v]) => bar(k, v)));
  const motivations = document.getElementById("motivations");
  motivations.replaceChildren(...Object.entries(s.motivations || {}).map(
    ([k, v]) => bar(k, v, (s.ranges || {})[k])));
  const frame = document.getElementById("frame");
  if (s.frame) frame.src = "data:image/jpeg;base64," + s.frame;
  else if (s.frame_src) frame.src = s.frame_src;
  document.getElementById("detections").textContent = (s.detections || []).map(
    d => `${d.cls} ${d.conf.toFixed(2)}`).join(", ");
  const tree = document.getElementById("tree");
  tree.replaceChildren(...(s.tree || "").split("\n").map(
    line => el("span", {class: statusClass(line)}, line + "\n")));
  const log = document.getElementById("dialogue");
  log.replaceChildren(...(s.dialogue || []).map(r => el("li", {},
    el("span", {class: "meta"}, `${r.t} s `), el("b", {}, r.input), " → ", r.text,
    el("span", {class: "meta"}, ` [${r.route}]`))));
  const care = document.getElementById("care");
  care.replaceChildren(...(s.care_alerts || []).map(a => el("li", {class: "alert"},
    el("span", {class: "meta"}, `${a.t} s `), el("b", {}, `${a.person}: ${a.care}`),
    ` "${a.text}"`)));
  document.body.dataset.updates = String(Number(document.body.dataset.updates) + 1);
  document.body.dataset.t = String(s.t || 0);
}

async function replay() {
  const index = await (await fetch("/api/replay")).json();
  const box = document.getElementById("replay");
  const slider = document.getElementById("slider");
  box.hidden = false;
  slider.max = String(index.duration);
  slider.step = String(index.step);
  let pending = null;
  const show = async () => {
    const t = Number(slider.value);
    document.getElementById("replay-t").textContent = `${t.toFixed(1)} / ${index.duration} s`;
    render(await (await fetch("/api/replay/at?t=" + t)).json());
  };
  slider.addEventListener("input", () => { clearTimeout(pending); pending = setTimeout(show, 50); });
  await show();
}

async function start() {
  const config = await (await fetch("/api/config")).json();
  document.body.dataset.kind = config.kind;
  if (config.kind === "replay") return replay();
  const source = new EventSource("/api/stream");
  source.onmessage = ev => render(JSON.parse(ev.data));
}

start();
