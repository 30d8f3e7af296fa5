// The page of `turtlectl web`: one WebSocket to the server (protocol: cli/web/protocol.py), the model
// every part draws from (window.turtlectl.model, which the tests read too), the toolbar and the
// keyboard and pad that drive.  world.js draws the map; panels.js the nodes, topics, plot, log and
// parameters.
import { World } from "./world.js";
import { Panels } from "./panels.js";

const model = {
  conn: "connecting",   // open | reconnecting | connecting
  router: "ok",         // ok | lost
  hello: null, world: null, can: { drive: false, command: false, edit: false },
  poses: {}, trails: {}, scans: {}, goals: {}, status: {}, outcomes: {},
  graph: { nodes: [], clients: [], topics: [] }, logs: [], echo: {}, replies: {},
  stats: { frames: 0, latencies: [], drawn: 0, reconnects: 0 },
  turtle: "turtle1",
  errors: [],
};
const app = { model, send: null, request: null, say: null };
window.turtlectl = app;

const $ = (id) => document.getElementById(id);
let socket = null, nextId = 1, backoff = 500;
const pending = new Map();

function say(text, kind = "") { const el = $("said"); el.textContent = el.title = text; el.className = "line " + kind; }
function banner(text, kind) { const el = $("banner"); el.textContent = text; el.className = kind || ""; }

function send(frame) {
  if (!socket || socket.readyState !== WebSocket.OPEN) return false;
  socket.send(JSON.stringify(frame));
  return true;
}

// A request with an id: resolves with the server's reply {ok, text, data}.
function request(frame) {
  const id = nextId++;
  return new Promise((resolve) => {
    pending.set(id, resolve);
    if (!send({ ...frame, id })) { pending.delete(id); resolve({ ok: false, text: "not connected to the page's server" }); }
  });
}
app.send = send;
app.say = say;
app.request = request;

function connect() {
  model.conn = model.hello ? "reconnecting" : "connecting";
  socket = new WebSocket(`${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/ws`);
  socket.onopen = () => {
    if (model.hello) { model.stats.reconnects += 1; banner("reconnected", "ok"); setTimeout(() => { if (model.conn === "open" && model.router === "ok") banner("", ""); }, 3000); }
    model.conn = "open"; backoff = 500;
    panels.watchAgain();
  };
  socket.onmessage = (event) => take(JSON.parse(event.data));
  socket.onclose = () => {
    const was = model.conn;
    model.conn = "reconnecting";
    drive.halt();  // nothing may drive on: the server stops the turtle too
    for (const resolve of pending.values()) resolve({ ok: false, text: "the connection to the page's server closed" });
    pending.clear();
    banner(`connection to the page's server lost: reconnecting${was === "open" ? "" : "…"}`, "warn");
    setTimeout(connect, backoff);
    backoff = Math.min(backoff * 2, 4000);
  };
}

function take(frame) {
  switch (frame.t) {
    case "hello":
      model.hello = frame; model.world = frame.world; model.can = frame.can;
      $("server").textContent = frame.server;
      $("role").textContent = frame.secure ? `logged in as ${frame.role}` : "";
      if (frame.router_lost) routerState("lost", "");
      enable();
      world.fitIfNew();
      break;
    case "world": model.world = frame.world; world.dirty = true; break;
    case "frame": takeFrame(frame); break;
    case "outcome": outcome(frame); break;
    case "graph": model.graph = frame; chooser(); panels.graph(frame); break;
    case "echo": model.echo[frame.key] = frame; panels.echo(frame); break;
    case "log":
      for (const r of frame.records) model.logs.push(r);
      if (model.logs.length > 2000) model.logs.splice(0, model.logs.length - 2000);
      panels.logs(frame.records);
      break;
    case "router": routerState(frame.state, frame.connect); break;
    case "reply": { const r = pending.get(frame.id); model.replies[frame.id] = frame; if (r) { pending.delete(frame.id); r(frame); } break; }
    case "error": model.errors.push(frame.text); say(frame.text, "bad"); break;
  }
}

function routerState(state, where) {
  model.router = state === "lost" ? "lost" : "ok";
  if (state === "lost") { drive.halt(); banner(`the system's router${where ? " at " + where : ""} is lost: waiting for it to come back`, "warn"); }
  else { banner("the system is back", "ok"); setTimeout(() => { if (model.router === "ok" && model.conn === "open") banner("", ""); }, 3000); }
}

function takeFrame(frame) {
  model.stats.frames += 1;
  let gone = false;
  for (const [turtle, pose] of Object.entries(frame.poses || {})) {
    if (pose === null) {  // killed: the chosen one goes to turtle1 (or another that is there)
      delete model.poses[turtle]; gone = true;
      if (turtle === model.turtle) { drive.halt(); const left = Object.keys(model.poses).sort(); model.turtle = left.includes("turtle1") ? "turtle1" : (left[0] || "turtle1"); }
      continue;
    }
    if (!(turtle in model.poses)) gone = true;  // a new one: the chooser lists it
    model.poses[turtle] = { ...pose, received: performance.timeOrigin + performance.now() };
    world.trail(turtle, pose);
  }
  for (const section of ["scans", "goals", "status"]) {
    for (const [turtle, fields] of Object.entries(frame[section] || {})) {
      if (fields === null) delete model[section][turtle]; else model[section][turtle] = fields;
    }
  }
  world.dirty = true;
  if (gone) chooser();
  showGoal();
}

function chooser() {
  const select = $("turtle");
  const names = Object.keys(model.poses).sort();
  if (!names.includes(model.turtle)) names.push(model.turtle);  // chosen, its first pose not here yet (spawned)
  if ([...select.options].map((o) => o.value).join() !== names.join()) {
    select.innerHTML = names.map((n) => `<option>${n}</option>`).join("");
    select.value = model.turtle;
  }
}

function enable() {
  for (const b of document.querySelectorAll("#pad button")) b.disabled = !model.can.drive;
  $("cancel").disabled = $("kill").disabled = !model.can.command;
  for (const input of document.querySelectorAll("input[name=mode]")) if (input.value !== "pan") input.disabled = !model.can.command;
  if (!model.can.drive) say(`this page's login (${model.hello.role}) may watch, not drive`, "");
}

// goals ---------------------------------------------------------------------------------------------

function showGoal() {
  const fb = model.goals[model.turtle];
  const el = $("goal");
  if (fb) {
    el.className = "line";
    el.textContent = `${model.turtle}: ${fb.state}, ${fb.distance_remaining.toFixed(2)} m to go, eta ${fb.eta.toFixed(1)} s, ${fb.elapsed.toFixed(1)} s so far`;
  } else if (model.outcomes[model.turtle]) {
    const o = model.outcomes[model.turtle];
    el.className = "line " + (o.success ? "good" : "bad");
    const errors = o.position_error == null ? "" : ` (off by ${o.position_error.toFixed(3)} m, ${o.heading_error.toFixed(1)}°)`;
    el.textContent = o.success ? `${o.turtle}: reached in ${o.time_taken.toFixed(1)} s${errors}` : `${o.turtle}: not reached (${o.reason}): ${o.detail || o.reason}, after ${Number(o.time_taken).toFixed(1)} s${errors}`;
  } else el.textContent = "";
  el.title = el.textContent;  // the whole line, when the map's width cuts it
}

function outcome(frame) { model.outcomes[frame.turtle] = frame; delete model.goals[frame.turtle]; world.dirty = true; showGoal(); }

async function act(frame, doing) {
  say(doing + "…");
  const reply = await request(frame);
  say(reply.text, reply.ok ? "good" : "bad");
  return reply;
}
// whether a navigator serves the turtle's goals (a spawned turtle has none unless a launch file gives it one)
function navigated(turtle) {
  const goals = model.graph.goals || [];
  return goals.includes(`${turtle}/navigate_to`) || (turtle === "turtle1" && goals.includes("navigate_to"));
}
app.navigated = navigated;
app.goal = (turtle, x, y, theta) => !navigated(turtle)
  ? (say(`${turtle} has no navigator (nothing serves ${turtle}/navigate_to): teleport it (shift+drag) or drive it (keys, pad)`, "bad"), Promise.resolve({ ok: false }))
  : act({ t: "goal", turtle, x, y, theta }, `${turtle}: goal (${x.toFixed(2)}, ${y.toFixed(2)}) ${theta.toFixed(0)}°`);
app.teleport = (turtle, x, y, theta) => act({ t: "teleport", turtle, x, y, theta }, `teleporting ${turtle}`);
app.spawn = (x, y, theta) => act({ t: "spawn", x, y, theta }, "spawning").then((r) => {
  if (r.ok && r.data) { model.turtle = r.data.name; say(`${r.text}: chosen now (the turtle list above the map)`, "good"); }
  return r;
});

// driving: the keys while the map has focus, and the pad ------------------------------------------------

const KEYS = { ArrowUp: "fwd", w: "fwd", W: "fwd", ArrowDown: "back", s: "back", S: "back", ArrowLeft: "left", a: "left", A: "left", ArrowRight: "right", d: "right", D: "right" };
const drive = {
  held: new Set(), timer: null, turtle: null, source: null, linear: 2.0, angular: 2.0,
  twist() {
    let v = 0, w = 0;
    if (this.held.has("fwd")) v += this.linear;
    if (this.held.has("back")) v -= this.linear;
    if (this.held.has("left")) w += this.angular;
    if (this.held.has("right")) w -= this.angular;
    return [v, w];
  },
  press(what, source) {
    if (!model.can.drive) { say(`this page's login (${model.hello ? model.hello.role : "?"}) cannot drive: run turtlectl web --role teleop`, "bad"); return; }
    if (model.router === "lost" || model.conn !== "open") return;
    if (what === "stop") { this.halt(); return; }
    this.held.add(what);
    this.source = source;
    this.turtle = this.turtle || model.turtle;
    this.tick();
    if (!this.timer) this.timer = setInterval(() => this.tick(), (model.hello.drive_repeat || 0.1) * 1000);
  },
  release(what) { this.held.delete(what); if (this.held.size === 0) this.halt(); else this.tick(); },
  tick() { const [v, w] = this.twist(); send({ t: "drive", turtle: this.turtle, linear: v, angular: w }); model.stats.driving = [v, w]; },
  halt() {
    const was = this.turtle;
    this.held.clear();
    if (this.timer) { clearInterval(this.timer); this.timer = null; }
    if (was) send({ t: "stop", turtle: was });
    this.turtle = null; this.source = null; model.stats.driving = [0, 0];
  },
};
app.drive = drive;

function keys() {
  const map = $("map");
  map.addEventListener("keydown", (e) => { const k = KEYS[e.key]; if (k) { e.preventDefault(); if (!e.repeat) drive.press(k, "keys"); } else if (e.key === " ") { e.preventDefault(); drive.halt(); } });
  map.addEventListener("keyup", (e) => { const k = KEYS[e.key]; if (k) { e.preventDefault(); drive.release(k); } });
  map.addEventListener("blur", () => { if (drive.source === "keys") drive.halt(); });  // the pad takes focus as it drives
  window.addEventListener("blur", () => drive.halt());
  document.addEventListener("visibilitychange", () => { if (document.hidden) drive.halt(); });
  for (const button of document.querySelectorAll("#pad button")) {
    const what = button.dataset.drive;
    button.addEventListener("pointerdown", (e) => { e.preventDefault(); button.setPointerCapture(e.pointerId); drive.press(what, "pad"); });
    for (const end of ["pointerup", "pointercancel", "lostpointercapture"]) button.addEventListener(end, () => { if (what !== "stop") drive.release(what); });
  }
}

// the toolbar -------------------------------------------------------------------------------------

function toolbar() {
  $("turtle").addEventListener("change", (e) => { drive.halt(); model.turtle = e.target.value; showGoal(); world.dirty = true; });
  $("cancel").addEventListener("click", () => act({ t: "cancel", turtle: model.turtle }, `canceling ${model.turtle}'s goal`));
  $("kill").addEventListener("click", () => act({ t: "kill", turtle: model.turtle }, `killing ${model.turtle}`));
  $("fit").addEventListener("click", () => world.fit());
  $("zoom-in").addEventListener("click", () => world.zoomBy(1.25));
  $("zoom-out").addEventListener("click", () => world.zoomBy(0.8));
  $("clear").addEventListener("click", () => { model.trails = {}; world.dirty = true; });
}
app.mode = () => document.querySelector("input[name=mode]:checked").value;

const world = new World($("map"), model, app);
const panels = new Panels(model, app);
app.world = world;
window.addEventListener("error", (e) => model.errors.push(String(e.message)));
toolbar();
keys();
connect();
