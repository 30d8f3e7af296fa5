// The map: the world as turtlesim draws it (its blue square), with the walls, the declared obstacles,
// every turtle (name, heading, trail, contact), its scan's rays and hits (what only the scan sees
// shows as hits where no obstacle is), a running goal's path and target; pan (right button, or the
// pan mode) and zoom (wheel).  A drag sets a goal's position and heading, as rviz's 2D Goal Pose;
// shift+drag teleports, alt+drag spawns.  It draws on the browser's frames, only when something
// changed, from the newest state: it never falls behind the poses.

const COLORS = ["#ffd54f", "#80deea", "#ef9a9a", "#a5d6a7", "#ce93d8", "#ffab91", "#b0bec5"];
const TRAIL_STEP = 0.02; // m between two trail points
const DRAG = 6; // px: a press released nearer than this is a click (focus only), not a gesture
const TRAIL_JUMP = 0.5; // m between two poses that no drive covers (a pose is 16 ms, 4 m/s at most): a teleport

export class World {
  constructor(canvas, model, app) {
    this.canvas = canvas; this.model = model; this.app = app;
    this.ctx = canvas.getContext("2d");
    this.scale = 40; this.ox = 20; this.oy = 20; this.fitted = false;
    this.dirty = true; this.drag = null; this.colors = {};
    new ResizeObserver(() => this.resize()).observe(canvas);
    canvas.addEventListener("pointerdown", (e) => this.down(e));
    canvas.addEventListener("pointermove", (e) => this.move(e));
    canvas.addEventListener("pointerup", (e) => this.up(e));
    canvas.addEventListener("pointercancel", () => { this.drag = null; this.dirty = true; });
    canvas.addEventListener("contextmenu", (e) => e.preventDefault());
    canvas.addEventListener("wheel", (e) => this.zoom(e), { passive: false });
    const loop = () => { if (this.dirty) this.draw(); requestAnimationFrame(loop); };
    requestAnimationFrame(loop);
  }

  // coordinates: world m (y up) <-> canvas CSS px (y down)
  toScreen(x, y) { return [this.ox + x * this.scale, this.h - (this.oy + y * this.scale)]; }
  toWorld(px, py) { return [(px - this.ox) / this.scale, (this.h - py - this.oy) / this.scale]; }
  // where on the page (client px) the world point (x, y) is: what a test clicks
  pagePoint(x, y) { const r = this.canvas.getBoundingClientRect(); const [sx, sy] = this.toScreen(x, y); return [r.left + sx, r.top + sy]; }

  resize() {
    const r = this.canvas.getBoundingClientRect(), dpr = window.devicePixelRatio || 1;
    this.w = r.width; this.h = r.height;
    this.canvas.width = Math.round(r.width * dpr); this.canvas.height = Math.round(r.height * dpr);
    this.ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    if (!this.fitted) this.fit(); else this.dirty = true;
  }
  fit() {
    const size = this.model.world ? this.model.world.size : 11.09;
    if (!this.w) return;
    this.scale = Math.min(this.w, this.h) * 0.94 / size;
    this.ox = (this.w - size * this.scale) / 2; this.oy = (this.h - size * this.scale) / 2;
    this.fitted = true; this.dirty = true;
  }
  fitIfNew() { if (!this.fittedWorld) { this.fittedWorld = true; this.fit(); } }
  color(turtle) { if (!this.colors[turtle]) this.colors[turtle] = COLORS[Object.keys(this.colors).length % COLORS.length]; return this.colors[turtle]; }

  trail(turtle, pose) {
    const trails = this.model.trails, keep = (this.model.hello && this.model.hello.trail) || 2000;
    const t = trails[turtle] || (trails[turtle] = []);
    const last = t.findLast((p) => p !== null);
    const step = last ? Math.hypot(last[0] - pose.x, last[1] - pose.y) : Infinity;
    if (last && step > TRAIL_JUMP) t.push(null);  // a teleport: the trail starts again there, no line across
    if (step >= TRAIL_STEP) { t.push([pose.x, pose.y]); if (t.length > keep) t.splice(0, t.length - keep); }
  }

  // gestures ----------------------------------------------------------------------------------------

  gesture(e) {
    if (e.button === 2 || e.button === 1) return "pan";
    if (e.shiftKey) return "teleport";
    if (e.altKey) return "spawn";
    return this.app.mode();
  }
  down(e) {
    this.canvas.focus();
    const what = this.gesture(e);
    if (what !== "pan" && !this.model.can.command) {
      const role = this.model.hello ? this.model.hello.role : "";
      this.app.say(`this page's login (${role}) can only watch: goals, teleport, spawn and kill need turtlectl web --role operator`, "bad");
    }
    const [px, py] = this.local(e);
    this.drag = { what: (what !== "pan" && !this.model.can.command) ? "pan" : what, from: [px, py], to: [px, py], o: [this.ox, this.oy] };
    this.canvas.setPointerCapture(e.pointerId);
    e.preventDefault();
  }
  move(e) {
    if (!this.drag) return;
    this.drag.to = this.local(e);
    if (this.drag.what === "pan") { this.ox = this.drag.o[0] + this.drag.to[0] - this.drag.from[0]; this.oy = this.drag.o[1] - (this.drag.to[1] - this.drag.from[1]); }
    this.dirty = true;
  }
  up(e) {
    const drag = this.drag; this.drag = null; this.dirty = true;
    if (!drag || drag.what === "pan") return;
    drag.to = this.local(e);
    const [x, y] = this.toWorld(...drag.from);
    const [dx, dy] = [drag.to[0] - drag.from[0], drag.from[1] - drag.to[1]];
    if (Math.hypot(dx, dy) < DRAG) {  // a click: the map's focus (for the keys), nothing sent
      this.app.say(`drag to ${drag.what === "goal" ? "send a goal" : drag.what}: press where the turtle should be, release towards where it should face`);
      return;
    }
    let theta = Math.atan2(dy, dx) * 180 / Math.PI;
    theta = ((theta % 360) + 360) % 360;
    const turtle = this.model.turtle;
    if (drag.what === "goal") this.app.goal(turtle, x, y, theta);
    else if (drag.what === "teleport") this.app.teleport(turtle, x, y, theta);
    else if (drag.what === "spawn") this.app.spawn(x, y, theta);
  }
  local(e) { const r = this.canvas.getBoundingClientRect(); return [e.clientX - r.left, e.clientY - r.top]; }
  // zoom by ``factor`` about the middle of the map (the buttons: a phone has no wheel)
  zoomBy(factor) {
    const [px, py] = [this.w / 2, this.h / 2], [wx, wy] = this.toWorld(px, py);
    this.scale = Math.max(5, Math.min(2000, this.scale * factor));
    this.ox = px - wx * this.scale; this.oy = this.h - py - wy * this.scale; this.dirty = true;
  }
  zoom(e) {
    e.preventDefault();
    const [px, py] = this.local(e), [wx, wy] = this.toWorld(px, py);
    this.scale = Math.max(5, Math.min(2000, this.scale * Math.exp(-e.deltaY * 0.0015)));
    this.ox = px - wx * this.scale; this.oy = this.h - py - wy * this.scale; this.dirty = true;
  }

  // drawing ----------------------------------------------------------------------------------------

  draw() {
    this.dirty = false;
    const { ctx, model } = this, world = model.world || { size: 11.09, obstacles: [], turtle_radius: 0.3 };
    ctx.clearRect(0, 0, this.w, this.h);
    ctx.fillStyle = "#dfe3ea"; ctx.fillRect(0, 0, this.w, this.h);
    const [x0, y0] = this.toScreen(0, world.size), side = world.size * this.scale;
    ctx.fillStyle = "#4556ff"; ctx.fillRect(x0, y0, side, side);  // turtlesim's blue
    ctx.strokeStyle = "#1a237e"; ctx.lineWidth = 3; ctx.strokeRect(x0, y0, side, side);  // the walls
    this.grid(world.size);
    ctx.fillStyle = "#90a4ae"; ctx.strokeStyle = "#37474f"; ctx.lineWidth = 1.5;
    for (const o of world.obstacles || []) { this.circle(o.x, o.y, o.radius); ctx.fill(); ctx.stroke(); }
    for (const [turtle, t] of Object.entries(model.trails)) this.polyline(t, this.color(turtle), 1.5);
    for (const [turtle, scan] of Object.entries(model.scans)) this.scan(turtle, scan);
    for (const [turtle, fb] of Object.entries(model.goals)) this.goal(turtle, fb);
    const now = performance.timeOrigin + performance.now();
    for (const [turtle, pose] of Object.entries(model.poses)) {
      this.turtle(turtle, pose, world.turtle_radius || 0.3);
      if (pose.stamp && !pose.drawn) { pose.drawn = now; this.latency(now - pose.stamp / 1e6); }
    }
    if (this.drag && this.drag.what !== "pan") this.preview();
    model.stats.drawn += 1;
  }
  latency(ms) { const l = this.model.stats.latencies; l.push(ms); if (l.length > 500) l.shift(); }
  grid(size) {
    const { ctx } = this; ctx.strokeStyle = "rgba(255,255,255,0.08)"; ctx.lineWidth = 1;
    for (let m = 1; m < size; m += 1) { this.line([m, 0], [m, size]); this.line([0, m], [size, m]); }
  }
  line(a, b) { const { ctx } = this; const [ax, ay] = this.toScreen(...a), [bx, by] = this.toScreen(...b); ctx.beginPath(); ctx.moveTo(ax, ay); ctx.lineTo(bx, by); ctx.stroke(); }
  circle(x, y, r) { const [sx, sy] = this.toScreen(x, y); this.ctx.beginPath(); this.ctx.arc(sx, sy, r * this.scale, 0, 2 * Math.PI); }
  polyline(points, color, width, dash) {
    if (points.length < 2) return;
    const { ctx } = this; ctx.strokeStyle = color; ctx.lineWidth = width; ctx.setLineDash(dash || []);
    ctx.beginPath();
    let pen = false;
    for (const point of points) {
      if (point === null) { pen = false; continue; }
      const [sx, sy] = this.toScreen(point[0], point[1]);
      if (pen) ctx.lineTo(sx, sy); else ctx.moveTo(sx, sy);
      pen = true;
    }
    ctx.stroke(); ctx.setLineDash([]);
  }
  scan(turtle, scan) {
    const pose = this.model.poses[turtle];
    let [ox, oy, ot] = scan.origin;
    if (ox === null || Number.isNaN(ox)) { if (!pose) return; [ox, oy, ot] = [pose.x, pose.y, pose.theta]; }
    const { ctx } = this;
    ctx.strokeStyle = "rgba(255,235,59,0.18)"; ctx.lineWidth = 1; ctx.fillStyle = "#ff5252";
    scan.ranges.forEach((r, i) => {
      const a = ot + scan.angle_min + i * scan.angle_increment;
      const reach = r === null ? scan.range_max : r;
      const end = [ox + reach * Math.cos(a), oy + reach * Math.sin(a)];
      this.line([ox, oy], end);
      if (r !== null) { const [sx, sy] = this.toScreen(...end); ctx.fillRect(sx - 2, sy - 2, 4, 4); }
    });
  }
  goal(turtle, fb) {
    const color = this.color(turtle);
    if (fb.path && fb.path.length) this.polyline(fb.path, color, 2, [6, 4]);
    this.arrow(fb.goal_x, fb.goal_y, fb.goal_theta * Math.PI / 180, color, 0.6);
    const { ctx } = this; const [sx, sy] = this.toScreen(fb.goal_x, fb.goal_y);
    ctx.strokeStyle = color; ctx.lineWidth = 2; ctx.beginPath(); ctx.arc(sx, sy, 6, 0, 2 * Math.PI); ctx.stroke();
  }
  arrow(x, y, heading, color, length) {
    const { ctx } = this; const tip = [x + length * Math.cos(heading), y + length * Math.sin(heading)];
    ctx.strokeStyle = color; ctx.lineWidth = 3; this.line([x, y], tip);
    const [tx, ty] = this.toScreen(...tip), back = heading + Math.PI;
    ctx.beginPath(); ctx.moveTo(tx, ty);
    for (const side of [0.5, -0.5]) { const [bx, by] = this.toScreen(tip[0] + 0.2 * Math.cos(back + side), tip[1] + 0.2 * Math.sin(back + side)); ctx.lineTo(bx, by); }
    ctx.closePath(); ctx.fillStyle = color; ctx.fill();
  }
  turtle(name, pose, radius) {
    const { ctx } = this; const [sx, sy] = this.toScreen(pose.x, pose.y), r = Math.max(radius * this.scale, 6);
    ctx.save(); ctx.translate(sx, sy); ctx.rotate(-pose.theta);
    ctx.fillStyle = this.color(name); ctx.strokeStyle = name === this.model.turtle ? "#fff" : "#263238"; ctx.lineWidth = 2;
    ctx.beginPath(); ctx.moveTo(r, 0); ctx.lineTo(-r * 0.7, r * 0.7); ctx.lineTo(-r * 0.35, 0); ctx.lineTo(-r * 0.7, -r * 0.7); ctx.closePath();
    ctx.fill(); ctx.stroke(); ctx.restore();
    if (pose.contact) { ctx.strokeStyle = "#ff1744"; ctx.lineWidth = 3; ctx.beginPath(); ctx.arc(sx, sy, r + 5, 0, 2 * Math.PI); ctx.stroke(); }
    ctx.font = "12px system-ui, sans-serif"; ctx.fillStyle = "#fff"; ctx.fillText(name + (pose.contact ? " (contact)" : ""), sx + r + 4, sy - r - 2);
  }
  preview() {
    const { from, to, what } = this.drag;
    const [x, y] = this.toWorld(...from), [dx, dy] = [to[0] - from[0], from[1] - to[1]];
    const color = what === "goal" ? "#00e676" : what === "teleport" ? "#ffea00" : "#ff80ab";
    this.arrow(x, y, Math.atan2(dy, dx), color, Math.max(0.5, Math.hypot(dx, dy) / this.scale));
  }
}
