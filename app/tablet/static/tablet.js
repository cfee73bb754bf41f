// The tablet page: a button per kind of conversation, a text box, the reply and its card,
// and feedback buttons. Replies that come later (during a run) are picked up by polling.
"use strict";

let lastSeq = 0;
let shownSeq = 0;
let pressed = null;   // the line last sent and when: its reply's latency is measured

async function post(path, body) {
  const r = await fetch(path, {method: "POST", headers: {"Content-Type": "application/json"},
    body: JSON.stringify(body)});
  const data = await r.json();
  if (!r.ok) throw new Error(data.error || data.detail || r.statusText);
  return data;
}

function show(reply) {
  if (reply.seq && reply.seq < shownSeq) return;
  shownSeq = reply.seq || shownSeq;
  document.getElementById("you").textContent = "You: " + reply.input;
  document.getElementById("reply-text").textContent = reply.text;
  document.getElementById("route").textContent = reply.route + (reply.found ? "" : " (not found)");
  renderCard(document.getElementById("card"), reply.card);
  document.body.dataset.seq = String(reply.seq || 0);
  if (pressed && reply.input === pressed.text) {
    // from the press to the reply and its card on screen (ms; read by bench/bench_tablet.py)
    document.body.dataset.latency = String(performance.now() - pressed.t0);
    pressed = null;
  }
}

async function say(text, mode) {
  pressed = {text, t0: performance.now()};
  document.getElementById("you").textContent = "You: " + text;
  document.getElementById("reply-text").textContent = "…";
  try {
    const reply = await post("/api/say", {text, mode});
    if (!reply.pending) show(reply);
  } catch (e) {
    document.getElementById("reply-text").textContent = "Sorry: " + e.message;
  }
}

async function poll() {
  try {
    const r = await fetch("/api/replies?after=" + lastSeq);
    const replies = await r.json();
    for (const reply of replies) {
      lastSeq = Math.max(lastSeq, reply.seq);
      if (reply.seq > shownSeq) show(reply);
    }
  } catch (e) { /* the next poll tries again */ }
  setTimeout(poll, 1000);
}

async function feedback(value) {
  const status = document.getElementById("fb-status");
  try {
    const r = await post("/api/feedback", {value});
    status.textContent = (value > 0 ? "Thank you!" : "Sorry, noted.") +
      (r.queued ? "" : " (" + r.note + ")");
  } catch (e) {
    status.textContent = "Sorry: " + e.message;
  }
}

async function start() {
  const config = await (await fetch("/api/config")).json();
  const kinds = document.getElementById("kinds");
  const text = document.getElementById("text");
  for (const b of config.buttons) {
    const button = el("button", {type: "button", id: "btn-" + b.kind, "data-kind": b.kind},
      b.label);
    button.addEventListener("click", () => say(text.value.trim() || b.line, b.kind));
    kinds.append(button);
  }
  document.getElementById("ask").addEventListener("submit", ev => {
    ev.preventDefault();
    if (text.value.trim()) say(text.value.trim(), "auto");
  });
  document.getElementById("fb-up").addEventListener("click", () => feedback(1));
  document.getElementById("fb-down").addEventListener("click", () => feedback(-1));
  const earlier = await (await fetch("/api/replies?after=0")).json();
  lastSeq = earlier.length ? earlier[earlier.length - 1].seq : 0;
  shownSeq = lastSeq;
  document.body.dataset.ready = "1";
  poll();
}

start();
