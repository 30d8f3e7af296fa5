// rqt's panels: the nodes (kind, pid, uptime, namespace), the topics (type, rate) with a live echo of
// one, a live plot of numeric fields, the log with level, node and text filters, and a node's
// parameters, edited with `turtlectl param set`'s checks and messages.
const $ = (id) => document.getElementById(id);
const esc = (s) => String(s).replace(/[&<>"']/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;" }[c]));
const LEVELS = { 10: "DEBUG", 20: "INFO", 30: "WARNING", 40: "ERROR", 50: "CRITICAL" };
const PLOT_SPAN = 30; // s of history drawn

export class Panels {
  constructor(model, app) {
    this.model = model; this.app = app;
    this.echoKey = null; this.plotKeys = new Set(); this.series = {}; this.plotted = new Set();
    this.paramNode = null;
    for (const tab of document.querySelectorAll("#tabs button")) tab.addEventListener("click", () => this.tab(tab.dataset.tab));
    for (const id of ["log-level", "log-node", "log-text"]) $(id).addEventListener("input", () => this.relog());
    $("param-node").addEventListener("change", (e) => this.loadParams(e.target.value));
    $("param-load").addEventListener("click", () => this.loadParams($("param-node").value));
    app.panels = this;
    const plotLoop = () => { if (this.plotDirty && $("panel-plot").classList.contains("on")) this.drawPlot(); requestAnimationFrame(plotLoop); };
    requestAnimationFrame(plotLoop);
  }
  tab(name) {
    for (const b of document.querySelectorAll("#tabs button")) b.classList.toggle("on", b.dataset.tab === name);
    for (const p of document.querySelectorAll(".panel")) p.classList.toggle("on", p.id === `panel-${name}`);
    if (name === "params" && !this.paramNode && $("param-node").value) this.loadParams($("param-node").value);
    this.plotDirty = true;
  }

  // nodes and topics ------------------------------------------------------------------------------

  graph(g) {
    $("nodes").tBodies[0].innerHTML = g.nodes.map((n) => `<tr class="pick" data-node="${esc(n.name)}"><td>${esc(n.name)}</td><td>${esc(n.kind)}</td><td>${esc(n.namespace)}</td><td>${n.pid}</td><td>${esc(n.host)}</td><td>${uptime(n.uptime)}</td></tr>`).join("");
    for (const row of $("nodes").tBodies[0].rows) row.addEventListener("click", () => { this.tab("params"); $("param-node").value = row.dataset.node; this.loadParams(row.dataset.node); });
    $("clients").tBodies[0].innerHTML = g.clients.map((c) => `<tr><td>${esc(c.name)}</td><td>${esc(c.tool)}</td><td>${c.pid}</td><td>${esc(c.host)}</td></tr>`).join("");
    $("topics").tBodies[0].innerHTML = g.topics.map((t) => `<tr class="pick${t.key === this.echoKey ? " chosen" : ""}" data-key="${esc(t.key)}"><td>${esc(t.key)}</td><td>${esc(t.type)}</td><td>${t.rate.toFixed(1)}</td><td><button data-plot="${esc(t.key)}">${this.plotKeys.has(t.key) ? "unplot" : "plot"}</button></td></tr>`).join("");
    for (const row of $("topics").tBodies[0].rows) row.addEventListener("click", (e) => { if (!e.target.dataset.plot) this.echoTopic(row.dataset.key); });
    for (const b of $("topics").querySelectorAll("button[data-plot]")) b.addEventListener("click", () => this.plotTopic(b.dataset.plot));
    const names = g.nodes.map((n) => n.name).sort();
    fill($("param-node"), names, this.paramNode);
    fill($("log-node"), ["", ...names], $("log-node").value, "every node");
  }
  echoTopic(key) {
    this.echoKey = key; $("echo-title").textContent = `echo: ${key}`; $("echo").textContent = "waiting for a message…";
    this.watch();
  }
  plotTopic(key) {
    if (this.plotKeys.has(key)) this.plotKeys.delete(key); else { this.plotKeys.add(key); this.tab("plot"); }
    this.watch();
  }
  watch() { this.app.send({ t: "watch", keys: [...new Set([...(this.echoKey ? [this.echoKey] : []), ...this.plotKeys])] }); }
  watchAgain() { if (this.echoKey || this.plotKeys.size) this.watch(); }
  echo(frame) {
    if (frame.key === this.echoKey) $("echo").textContent = `${frame.type}\n${JSON.stringify(frame.message, null, 2)}`;
    if (this.plotKeys.has(frame.key)) this.sample(frame);
  }

  // the plot -------------------------------------------------------------------------------------

  sample(frame) {
    const now = performance.now() / 1000;
    for (const [field, value] of numbers(frame.message)) {
      const name = `${frame.key}.${field}`;
      if (!this.series[name]) { this.series[name] = []; this.fields(); }
      const s = this.series[name]; s.push([now, value]);
      while (s.length && s[0][0] < now - PLOT_SPAN) s.shift();
    }
    this.plotDirty = true;
  }
  fields() {
    $("plot-fields").innerHTML = Object.keys(this.series).sort().map((n) => `<label><input type="checkbox" data-series="${esc(n)}"${this.plotted.has(n) ? " checked" : ""}> ${esc(n)}</label>`).join("");
    for (const box of $("plot-fields").querySelectorAll("input")) box.addEventListener("change", () => { if (box.checked) this.plotted.add(box.dataset.series); else this.plotted.delete(box.dataset.series); this.plotDirty = true; });
  }
  drawPlot() {
    this.plotDirty = false;
    const canvas = $("plot"), ctx = canvas.getContext("2d"), w = canvas.width = canvas.clientWidth, h = canvas.height = canvas.clientHeight;
    ctx.clearRect(0, 0, w, h);
    const chosen = [...this.plotted].filter((n) => this.series[n] && this.series[n].length);
    if (!chosen.length) { ctx.fillStyle = "#888"; ctx.fillText("plot a topic (topics tab), then tick its fields", 10, 20); return; }
    const now = performance.now() / 1000;
    let lo = Infinity, hi = -Infinity;
    for (const n of chosen) for (const [, v] of this.series[n]) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    if (hi - lo < 1e-9) { hi += 1; lo -= 1; }
    const X = (t) => 40 + (t - (now - PLOT_SPAN)) / PLOT_SPAN * (w - 50), Y = (v) => h - 20 - (v - lo) / (hi - lo) * (h - 30);
    ctx.strokeStyle = "#ccc"; ctx.strokeRect(40, 10, w - 50, h - 30); ctx.fillStyle = "#555";
    ctx.fillText(hi.toPrecision(4), 2, 14); ctx.fillText(lo.toPrecision(4), 2, h - 20); ctx.fillText(`last ${PLOT_SPAN} s`, w - 70, h - 5);
    const colors = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"];
    $("plot-legend").replaceChildren(...chosen.map((n, i) => { const s = document.createElement("span"); s.style.color = colors[i % colors.length]; s.textContent = `■ ${n} = ${this.series[n].at(-1)[1].toPrecision(5)}  `; return s; }));
    chosen.forEach((n, i) => {
      ctx.strokeStyle = colors[i % colors.length]; ctx.lineWidth = 1.5; ctx.beginPath();
      this.series[n].forEach(([t, v], j) => { if (j) ctx.lineTo(X(t), Y(v)); else ctx.moveTo(X(t), Y(v)); });
      ctx.stroke();
    });
  }

  // the log ----------------------------------------------------------------------------------------

  logs(records) { const box = $("log"), atEnd = box.scrollTop + box.clientHeight >= box.scrollHeight - 4; for (const r of records) if (this.shows(r)) box.append(line(r)); trim(box); if (atEnd) box.scrollTop = box.scrollHeight; }
  shows(r) { const node = $("log-node").value, text = $("log-text").value; return r.level >= Number($("log-level").value) && (!node || r.node === node) && (!text || r.message.includes(text)); }
  relog() { const box = $("log"); box.innerHTML = ""; for (const r of this.model.logs) if (this.shows(r)) box.append(line(r)); trim(box); box.scrollTop = box.scrollHeight; }

  // parameters -------------------------------------------------------------------------------------

  async loadParams(node) {
    if (!node) return;
    this.paramNode = node;
    const reply = await this.app.request({ t: "params", node });
    const said = $("param-said");
    if (!reply.ok) { said.textContent = reply.text; said.className = "bad"; return; }
    said.textContent = ""; said.className = "";
    const editable = this.model.can.edit;
    $("params").tBodies[0].innerHTML = reply.data.parameters.map((p) => `<tr><td title="${esc(p.type)}">${esc(p.name)}</td><td>${p.run_time && editable ? `<input data-param="${esc(p.name)}" data-value="${esc(shown(p.value))}" value="${esc(shown(p.value))}">` : `<span title="${esc(p.fixed_because || "")}">${esc(shown(p.value))}</span>`}</td><td>${esc(p.unit)}</td><td>${esc(p.range)}</td><td>${esc(p.meaning)}</td></tr>`).join("");
    for (const input of $("params").querySelectorAll("input[data-param]")) input.addEventListener("keydown", (e) => { if (e.key === "Enter") this.setParam(node, input); });
  }
  async setParam(node, input) {
    const said = $("param-said");
    said.textContent = `setting ${node} ${input.dataset.param}…`; said.className = "";
    const reply = await this.app.request({ t: "set_param", node, name: input.dataset.param, value: input.value });
    said.textContent = reply.text; said.className = reply.ok ? "good" : "bad";
    input.classList.toggle("bad", !reply.ok);
    if (reply.ok) input.dataset.value = input.value;
    else input.value = input.dataset.value;  // the value in force: the node kept it
    this.model.lastParamReply = reply;
  }
}

function numbers(value, prefix = "") {
  const out = [];
  if (typeof value === "number") out.push([prefix, value]);
  else if (typeof value === "boolean") out.push([prefix, value ? 1 : 0]);
  else if (value && typeof value === "object" && !Array.isArray(value)) for (const [k, v] of Object.entries(value)) if (k !== "stamp" && k !== "seq") out.push(...numbers(v, prefix ? `${prefix}.${k}` : k));
  return out.filter(([name]) => name);
}
function shown(v) { return typeof v === "object" ? JSON.stringify(v) : String(v); }
function uptime(s) { return s < 60 ? `${s.toFixed(0)} s` : s < 3600 ? `${(s / 60).toFixed(1)} min` : `${(s / 3600).toFixed(1)} h`; }
function line(r) { const d = document.createElement("div"); d.className = `l${r.level}`; d.textContent = `${new Date(r.stamp / 1e6).toLocaleTimeString()} ${LEVELS[r.level] || r.level} [${r.node}] ${r.message}`; return d; }
function trim(box) { while (box.childElementCount > 1000) box.firstChild.remove(); }
function fill(select, values, keep, blank) {
  if ([...select.options].map((o) => o.value).join() === values.join()) return;
  select.innerHTML = values.map((v) => `<option value="${esc(v)}">${esc(v || blank)}</option>`).join("");
  if (keep !== null && values.includes(keep)) select.value = keep;
}
