// jointgap report: builds the page from the embedded data (script#jg-data): the
// mechanism's animation, the journal orbits, the plots with a cursor at the
// animation's time, the comparison and study sections, and the tables.
"use strict";

const SVG_NS = "http://www.w3.org/2000/svg";
const MODE_NAMES = ["free flight", "impact", "continuous contact"];
const MODE_COLOURS = ["#1f77b4", "#d62728", "#2ca02c"];
const SPEEDS = [0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1];

function el(tag, attrs, parent, text) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (k === "class") e.className = v;
    else e.setAttribute(k, v);
  }
  if (text !== undefined) e.textContent = text;
  if (parent) parent.appendChild(e);
  return e;
}

function svg(tag, attrs, parent) {
  const e = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, String(v));
  if (parent) parent.appendChild(e);
  return e;
}

function section(id, title) {
  const s = el("section", { id, class: "jg-section" }, document.getElementById("report"));
  el("h2", {}, s, title);
  return s;
}

function cssId(name) {
  return String(name).replace(/[^A-Za-z0-9_-]/g, "_");
}

// ------------------------------------------------------------------------ tables

function renderTable(parent, table, onSeek) {
  const box = el("div", { class: "jg-table-box" }, parent);
  el("h3", {}, box, table.title);
  if (table.note) el("p", { class: "jg-note" }, box, table.note);
  const holder = table.rows.length > 14 ? el("div", { class: "jg-scroll" }, box) : box;
  const t = el("table", { id: table.id, class: "jg-table" + (table.columns[0] === "" ? " jg-kv" : "") }, holder);
  const keyValue = table.columns.every((c) => c === "");
  if (!keyValue) {
    const tr = el("tr", {}, el("thead", {}, t));
    table.columns.forEach((c, k) => {
      const th = el("th", {}, tr, c);
      if (table.sortable) {
        th.classList.add("jg-sortable");
        th.title = "sort";
        th.addEventListener("click", () => sortTable(t, k, table));
      }
    });
  }
  const body = el("tbody", {}, t);
  fillRows(body, table.rows, table, onSeek);
  return t;
}

function fillRows(body, rows, table, onSeek) {
  body.textContent = "";
  rows.forEach((row, k) => {
    const tr = el("tr", {}, body);
    const cls = table.row_classes && table.row_classes[row.__index !== undefined ? row.__index : k];
    if (cls) tr.className = cls;
    row.forEach((cell) => el("td", { class: typeof cell === "number" ? "num" : "" }, tr, jgFormat(cell)));
    if (table.seek !== null && table.seek !== undefined && typeof row[table.seek] === "number" && onSeek) {
      tr.classList.add("jg-seek");
      tr.dataset.time = String(row[table.seek]);
      tr.addEventListener("click", () => onSeek(row[table.seek]));
    }
  });
}

function sortTable(t, k, table) {
  const down = t.dataset.sortColumn === String(k) && t.dataset.sortOrder !== "desc";
  const rows = table.rows.map((r, i) => Object.assign(r.slice(), { __index: i }));
  rows.sort((a, b) => {
    const x = a[k];
    const y = b[k];
    if (x === y) return 0;
    if (x === null) return 1;
    if (y === null) return -1;
    const c = typeof x === "number" && typeof y === "number" ? x - y : String(x).localeCompare(String(y));
    return down ? -c : c;
  });
  t.dataset.sortColumn = String(k);
  t.dataset.sortOrder = down ? "desc" : "asc";
  fillRows(t.querySelector("tbody"), rows, table, t._onSeek);
}

// ------------------------------------------------------------------------ mechanism

class Mechanism {
  constructor(parent, run) {
    this.run = run;
    this.scene = run.scene;
    this.frames = run.frames;
    const b = this.scene.bounds;
    const size = Math.max(b[2] - b[0], b[3] - b[1]);
    const pad = 0.08 * size;
    this.home = [b[0] - pad, -(b[3] + pad), b[2] - b[0] + 2 * pad, b[3] - b[1] + 2 * pad];
    this.viewBox = this.home.slice();
    this.svg = svg("svg", { id: "mechanism", class: "jg-mechanism", preserveAspectRatio: "xMidYMid meet" }, parent);
    this.svg.style.aspectRatio = String(this.home[2] / this.home[3]); // CSS bounds the height
    this._setViewBox();
    const world = svg("g", { transform: "scale(1,-1)" }, this.svg);
    this.ground = svg("g", { id: "ground" }, world);
    this.ghostLayer = svg("g", { id: "ghost", opacity: "0.28" }, world);
    this.bodyLayer = svg("g", { id: "bodies" }, world);
    this.jointLayer = svg("g", { id: "joints" }, world);
    this.groups = {};
    this.ghosts = {};
    this._drawGround(size);
    for (const body of this.scene.bodies) {
      this.groups[body.name] = this._drawBody(this.bodyLayer, body, "body-" + cssId(body.name), false);
      if (this.frames.ideal && this.frames.ideal[body.name]) {
        this.ghosts[body.name] = this._drawBody(this.ghostLayer, body, "ghost-" + cssId(body.name), true);
      }
    }
    this.journals = {};
    for (const c of this.scene.clearances) {
      const owner = c.bearing_body === null ? this.ground : this.groups[c.bearing_body];
      svg("circle", { class: "jg-bearing", cx: c.point[0], cy: c.point[1], r: c.drawn_bearing_radius, "vector-effect": "non-scaling-stroke" }, owner);
      this.journals[c.joint] = svg(
        "circle",
        { id: "journal-" + cssId(c.joint), class: "jg-journal", r: c.drawn_journal_radius, "vector-effect": "non-scaling-stroke" },
        this.jointLayer
      );
    }
    this._listen();
  }

  _setViewBox() {
    this.svg.setAttribute("viewBox", this.viewBox.join(" "));
  }

  _drawGround(size) {
    const r = this.scene.pin_radius;
    for (const g of this.scene.ground.guides) {
      const parent = g.body === null ? this.ground : null;
      if (!parent) continue;
      const [ax, ay] = g.axis;
      const n = Math.hypot(ax, ay) || 1;
      const L = 4 * size;
      svg("line", {
        class: "jg-guide",
        x1: g.point[0] - (L * ax) / n,
        y1: g.point[1] - (L * ay) / n,
        x2: g.point[0] + (L * ax) / n,
        y2: g.point[1] + (L * ay) / n,
        "vector-effect": "non-scaling-stroke",
      }, parent);
    }
    for (const p of this.scene.ground.pins) {
      const s = 2.6 * r;
      svg("path", {
        class: "jg-ground",
        d: `M ${p[0]} ${p[1]} L ${p[0] - s} ${p[1] - 1.7 * s} L ${p[0] + s} ${p[1] - 1.7 * s} Z`,
        "vector-effect": "non-scaling-stroke",
      }, this.ground);
    }
  }

  _drawBody(layer, body, id, ghost) {
    const g = svg("g", { id, class: ghost ? "jg-ghost" : "jg-body" }, layer);
    g.dataset.body = body.name;
    const colour = ghost ? "#666" : null;
    // Thin lines from the centre of mass to the joint points: a shape that does not
    // reach a joint (a pendulum's bob) still shows what holds it.
    for (const p of body.links || []) {
      if (p[0] !== 0 || p[1] !== 0) svg("line", { class: "jg-link", x1: 0, y1: 0, x2: p[0], y2: p[1], "vector-effect": "non-scaling-stroke" }, g);
    }
    for (const s of body.shapes) {
      if (s.type === "bar") {
        svg("line", { class: "jg-bar-outline", x1: s.from[0], y1: s.from[1], x2: s.to[0], y2: s.to[1], "stroke-width": s.width }, g);
        const line = svg("line", { class: "jg-bar", x1: s.from[0], y1: s.from[1], x2: s.to[0], y2: s.to[1], "stroke-width": s.width * 0.86 }, g);
        if (colour) line.style.stroke = colour;
      } else if (s.type === "path") {
        const pts = s.points.map((p) => p.join(",")).join(" ");
        svg("polyline", { class: "jg-bar-outline", points: pts, "stroke-width": s.width }, g);
        svg("polyline", { class: "jg-bar", points: pts, "stroke-width": s.width * 0.86 }, g);
      } else if (s.type === "block") {
        svg("rect", {
          class: "jg-block", x: -s.width / 2, y: -s.height / 2, width: s.width, height: s.height,
          rx: 0.06 * Math.min(s.width, s.height), "vector-effect": "non-scaling-stroke",
        }, g);
      } else if (s.type === "disk") {
        svg("circle", { class: "jg-block", r: s.radius, "vector-effect": "non-scaling-stroke" }, g);
      }
    }
    if (!ghost) {
      for (const p of body.pins) {
        svg("circle", { class: "jg-pin", cx: p[0], cy: p[1], r: this.scene.pin_radius, "vector-effect": "non-scaling-stroke" }, g);
      }
    }
    return g;
  }

  show(k) {
    const f = this.frames;
    for (const [name, g] of Object.entries(this.groups)) {
      const b = f.bodies[name];
      g.setAttribute("transform", pose(b.x[k], b.y[k], b.angle[k]));
    }
    for (const [name, g] of Object.entries(this.ghosts)) {
      const b = f.ideal[name];
      if (b.x[k] === null) g.setAttribute("visibility", "hidden");
      else {
        g.removeAttribute("visibility");
        g.setAttribute("transform", pose(b.x[k], b.y[k], b.angle[k]));
      }
    }
    for (const c of this.scene.clearances) {
      const j = f.joints[c.joint];
      let cx = c.point[0];
      let cy = c.point[1];
      let a = 0;
      if (c.bearing_body !== null) {
        const b = f.bodies[c.bearing_body];
        a = b.angle[k];
        const ca = Math.cos(a);
        const sa = Math.sin(a);
        [cx, cy] = [b.x[k] + ca * c.point[0] - sa * c.point[1], b.y[k] + sa * c.point[0] + ca * c.point[1]];
      }
      const m = this.scene.magnify;
      const ex = j.ex[k] || 0;
      const ey = j.ey[k] || 0;
      const gx = Math.cos(a) * ex - Math.sin(a) * ey;
      const gy = Math.sin(a) * ex + Math.cos(a) * ey;
      const journal = this.journals[c.joint];
      journal.setAttribute("cx", (cx + m * gx).toPrecision(9));
      journal.setAttribute("cy", (cy + m * gy).toPrecision(9));
      journal.style.fill = MODE_COLOURS[j.mode[k]] || "#888";
    }
  }

  setGhost(visible) {
    this.ghostLayer.style.display = visible ? "" : "none";
  }

  _listen() {
    let drag = null;
    this.svg.addEventListener("wheel", (e) => {
      e.preventDefault();
      const r = this.svg.getBoundingClientRect();
      const scale = Math.max(this.viewBox[2] / r.width, this.viewBox[3] / r.height);
      const cx = this.viewBox[0] + this.viewBox[2] / 2 + (e.clientX - r.left - r.width / 2) * scale;
      const cy = this.viewBox[1] + this.viewBox[3] / 2 + (e.clientY - r.top - r.height / 2) * scale;
      const f = Math.pow(1.0015, e.deltaY);
      const [x, y, w, h] = this.viewBox;
      this.viewBox = [cx - (cx - x) * f, cy - (cy - y) * f, w * f, h * f];
      this._setViewBox();
    }, { passive: false });
    this.svg.addEventListener("pointerdown", (e) => {
      drag = { x: e.clientX, y: e.clientY, box: this.viewBox.slice() };
      this.svg.setPointerCapture(e.pointerId);
    });
    this.svg.addEventListener("pointermove", (e) => {
      if (!drag) return;
      const r = this.svg.getBoundingClientRect();
      const scale = Math.max(drag.box[2] / r.width, drag.box[3] / r.height);
      this.viewBox = [drag.box[0] - (e.clientX - drag.x) * scale, drag.box[1] - (e.clientY - drag.y) * scale, drag.box[2], drag.box[3]];
      this._setViewBox();
    });
    const end = () => (drag = null);
    this.svg.addEventListener("pointerup", end);
    this.svg.addEventListener("pointercancel", end);
    this.svg.addEventListener("dblclick", () => {
      this.viewBox = this.home.slice();
      this._setViewBox();
    });
  }
}

function pose(x, y, angle) {
  return `translate(${x} ${y}) rotate(${((angle * 180) / Math.PI).toPrecision(8)})`;
}

// ------------------------------------------------------------------------ orbits

class Orbit {
  constructor(parent, orbit, frames) {
    this.orbit = orbit;
    this.frames = frames.joints[orbit.joint];
    const box = el("div", { class: "jg-orbit", "data-joint": orbit.joint }, parent);
    el("h3", {}, box, `${orbit.joint}: journal centre [µm]`);
    const um = 1e6;
    let reach = orbit.clearance;
    for (let i = 0; i < orbit.ex.length; i++) {
      if (orbit.ex[i] !== null) reach = Math.max(reach, Math.hypot(orbit.ex[i], orbit.ey[i]));
    }
    const R = 1.12 * reach * um;
    this.svg = svg("svg", { id: "orbit-" + cssId(orbit.joint), viewBox: `${-R} ${-R} ${2 * R} ${2 * R}`, class: "jg-orbit-svg" }, box);
    const g = svg("g", { transform: "scale(1,-1)" }, this.svg);
    svg("line", { class: "jg-axis", x1: -R, y1: 0, x2: R, y2: 0, "vector-effect": "non-scaling-stroke" }, g);
    svg("line", { class: "jg-axis", x1: 0, y1: -R, x2: 0, y2: R, "vector-effect": "non-scaling-stroke" }, g);
    svg("circle", { class: "jg-clearance", r: orbit.clearance * um, "vector-effect": "non-scaling-stroke" }, g);
    let start = 0;
    const n = orbit.ex.length;
    for (let i = 1; i <= n; i++) {
      if (i === n || orbit.mode[i] !== orbit.mode[start]) {
        const pts = [];
        for (let k = start; k <= Math.min(i, n - 1); k++) {
          if (orbit.ex[k] !== null) pts.push(`${(orbit.ex[k] * um).toFixed(3)},${(orbit.ey[k] * um).toFixed(3)}`);
        }
        svg("polyline", { class: "jg-trace", points: pts.join(" "), stroke: MODE_COLOURS[orbit.mode[start]] || "#888", "vector-effect": "non-scaling-stroke" }, g);
        start = i;
      }
    }
    this.trail = svg("polyline", { class: "jg-trail", points: "", "vector-effect": "non-scaling-stroke" }, g);
    this.marker = svg("circle", { id: "orbit-marker-" + cssId(orbit.joint), class: "jg-marker", r: 0.045 * R, "vector-effect": "non-scaling-stroke" }, g);
    const legend = el("div", { class: "jg-mode-legend" }, box);
    MODE_NAMES.forEach((name, k) => {
      const item = el("span", {}, legend);
      el("span", { class: "jg-swatch" }, item).style.borderColor = MODE_COLOURS[k];
      item.appendChild(document.createTextNode(name));
    });
    el("p", { class: "jg-note" }, box, `bearing frame${orbit.bearing_body ? " (" + orbit.bearing_body + ")" : ""}; dashed: the clearance circle, radius ${jgFormat(orbit.clearance * um)} µm${orbit.thinned ? `; drawn through ${orbit.ex.length} of ${orbit.thinned} samples, evenly along the path` : ""}`);
    this.readout = el("p", { class: "jg-readout" }, box, "");
  }

  show(k) {
    const f = this.frames;
    const um = 1e6;
    const x = (f.ex[k] || 0) * um;
    const y = (f.ey[k] || 0) * um;
    this.marker.setAttribute("cx", x.toFixed(3));
    this.marker.setAttribute("cy", y.toFixed(3));
    this.marker.style.fill = MODE_COLOURS[f.mode[k]] || "#888";
    const pts = [];
    for (let i = Math.max(0, k - 40); i <= k; i++) {
      if (f.ex[i] !== null) pts.push(`${(f.ex[i] * um).toFixed(3)},${(f.ey[i] * um).toFixed(3)}`);
    }
    this.trail.setAttribute("points", pts.join(" "));
    const e = Math.hypot(x, y);
    this.readout.textContent = `|e| = ${e.toFixed(1)} µm, ${MODE_NAMES[f.mode[k]] || "-"}`;
  }
}

// ------------------------------------------------------------------------ player

class Player {
  constructor(parent, run, views) {
    this.time = run.frames.time;
    this.views = views;
    this.k = 0;
    this.t = this.time[0];
    this.playing = false;
    const duration = this.time[this.time.length - 1] - this.time[0];
    this.speed = SPEEDS.filter((s) => s <= duration / 15).pop() || SPEEDS[0];
    const bar = el("div", { class: "jg-controls" }, parent);
    this.button = el("button", { type: "button", id: "play", class: "jg-button" }, bar, "▶ play");
    this.button.addEventListener("click", () => (this.playing ? this.pause() : this.play()));
    const label = el("label", {}, bar, "speed ");
    this.select = el("select", { id: "speed" }, label);
    for (const s of SPEEDS) {
      const o = el("option", { value: String(s) }, this.select, `${s} × real time`);
      if (s === this.speed) o.selected = true;
    }
    this.select.addEventListener("change", () => (this.speed = Number(this.select.value)));
    this.slider = el("input", { type: "range", id: "time-slider", min: "0", max: String(this.time.length - 1), step: "1", value: "0" }, bar);
    this.slider.addEventListener("input", () => this.showFrame(Number(this.slider.value)));
    this.readout = el("span", { id: "time-readout", class: "jg-readout" }, bar, "");
    this._tick = this._tick.bind(this);
  }

  play() {
    if (this.k >= this.time.length - 1) this.showFrame(0);
    this.playing = true;
    this.button.textContent = "❚❚ pause";
    this.last = null;
    requestAnimationFrame(this._tick);
  }

  pause() {
    this.playing = false;
    this.button.textContent = "▶ play";
  }

  _tick(now) {
    if (!this.playing) return;
    if (this.last !== null) {
      this.t += ((now - this.last) / 1000) * this.speed;
      const end = this.time[this.time.length - 1];
      if (this.t > end) this.t = this.time[0] + ((this.t - this.time[0]) % (end - this.time[0] || 1));
      const k = Math.max(0, jgLowerBound(this.time, this.t + 1e-12) - 1);
      if (k !== this.k) this.showFrame(k, true);
    }
    this.last = now;
    requestAnimationFrame(this._tick);
  }

  seek(t) {
    let k = jgLowerBound(this.time, t);
    if (k > 0 && (k === this.time.length || t - this.time[k - 1] < this.time[k] - t)) k -= 1;
    this.showFrame(Math.min(k, this.time.length - 1));
  }

  showFrame(k, fromClock) {
    this.k = k;
    if (!fromClock) this.t = this.time[k];
    this.slider.value = String(k);
    for (const v of this.views) v.show(k, this.time[k]);
    this.readout.textContent = `t = ${this.time[k].toFixed(5)} s (frame ${k + 1} of ${this.time.length})`;
  }
}

// ------------------------------------------------------------------------ 3D view (spatial runs)

// plotly.js (inlined only in a spatial run's page) draws the mechanism and the orbits
// in WebGL scenes: drag rotates, wheel zooms, its mode bar pans and resets.
const AXIS_COLOURS = ["#d62728", "#2ca02c", "#1f77b4"];
const MODE_SCALE = [[0, MODE_COLOURS[0]], [0.5, MODE_COLOURS[1]], [1, MODE_COLOURS[2]]];
const PLOTLY_CONFIG = { displaylogo: false, responsive: true };

// v turned by the unit quaternion q = [e0, e1, e2, e3] (scalar first).
function qRotate(q, v) {
  const [w, x, y, z] = q;
  const tx = 2 * (y * v[2] - z * v[1]);
  const ty = 2 * (z * v[0] - x * v[2]);
  const tz = 2 * (x * v[1] - y * v[0]);
  return [v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz), v[2] + w * tz + (x * ty - y * tx)];
}

// Redraws a plotly view at the latest frame asked for, one redraw at a time: frames
// asked for while one is drawn are skipped, never queued. `dataset.frame` says which
// frame the view shows once it is drawn.
class View3D {
  constructor(div, traces, layout) {
    this.div = div;
    this.busy = false;
    this.want = null;
    this.ready = Plotly.newPlot(div, traces, layout, PLOTLY_CONFIG);
  }

  show(k) {
    this.want = k;
    if (!this.busy) this._draw();
  }

  _draw() {
    this.busy = true;
    const k = this.want;
    this.ready
      .then(() => this.update(k))
      .then(() => {
        this.div.dataset.frame = String(k);
        this.busy = false;
        if (this.want !== k) this._draw();
      })
      .catch((e) => console.error(e));
  }
}

// A scene with fixed axes over the box lo..hi (padded), in true proportions: the
// axes do not rescale as the mechanism moves.
function scene3d(title, lo, hi) {
  const span = Math.max(...[0, 1, 2].map((c) => hi[c] - lo[c]), 1e-12);
  const pad = 0.08 * span;
  const ranges = [0, 1, 2].map((c) => [lo[c] - pad, hi[c] + pad]);
  const axis = (c) => ({ title: { text: `${"xyz"[c]}${title}` }, range: ranges[c], autorange: false, showspikes: false });
  const ratio = (c) => (ranges[c][1] - ranges[c][0]) / (span + 2 * pad);
  return {
    scene: {
      aspectmode: "manual",
      aspectratio: { x: ratio(0), y: ratio(1), z: ratio(2) },
      xaxis: axis(0),
      yaxis: axis(1),
      zaxis: axis(2),
    },
    margin: { l: 0, r: 0, t: 10, b: 0 },
    uirevision: "keep",
    showlegend: true,
    legend: { x: 0, y: 1 },
  };
}

class Mechanism3D extends View3D {
  constructor(parent, run) {
    const scene = run.scene;
    const div = el("div", { id: "mechanism-3d", class: "jg-3d" }, parent);
    const line = (name, colour, width, extra) =>
      Object.assign({ type: "scatter3d", mode: "lines", name, x: [], y: [], z: [], line: { color: colour, width } }, extra || {});
    const traces = scene.bodies.map((b) =>
      line(b.name, "#34495e", 7, { mode: "lines+markers", marker: { size: 3, color: "#34495e" } })
    );
    AXIS_COLOURS.forEach((c, k) => traces.push(line(k === 0 ? "body frames (x, y, z)" : `body frames ${"xyz"[k]}`, c, 4, { showlegend: k === 0 })));
    traces.push({ type: "scatter3d", mode: "markers", name: "joints", x: [], y: [], z: [], text: scene.joints.map((j) => j.name), hoverinfo: "text", marker: { size: 5, color: "#ffffff", line: { color: "#111", width: 1 } } });
    traces.push({ type: "scatter3d", mode: "markers", name: `pins (clearance × ${jgFormat(scene.magnify)})`, x: [], y: [], z: [], text: scene.clearances.map((c) => c.joint), hoverinfo: "text", marker: { size: 6, color: [], cmin: 0, cmax: 2, colorscale: MODE_SCALE } });
    traces.push({ type: "scatter3d", mode: "markers", name: "markers", x: [], y: [], z: [], text: scene.markers.map((m) => m.name), hoverinfo: "text", marker: { size: 4, color: "#ff7f0e" } });
    const dynamic = traces.map((_, k) => k);
    for (const p of scene.paths) {
      const style = p.ideal ? { color: "#555", width: 2, dash: "dash" } : { color: "#ff7f0e", width: 2 };
      traces.push(line(`${p.marker} path${p.ideal ? " (ideal)" : ""}`, null, 2, { x: p.x, y: p.y, z: p.z, opacity: 0.7, line: style }));
    }
    if (scene.ground.length) {
      traces.push({ type: "scatter3d", mode: "markers", name: "ground points", x: scene.ground.map((p) => p[0]), y: scene.ground.map((p) => p[1]), z: scene.ground.map((p) => p[2]), text: scene.ground_names, hoverinfo: "text", marker: { size: 4, symbol: "square", color: "#777" } });
    }
    super(div, traces, scene3d(" [m]", scene.bounds[0], scene.bounds[1]));
    this.run = run;
    this.scene = scene;
    this.frames = run.frames;
    this.dynamic = dynamic;
  }

  // A point of a body (its model frame) in global axes at frame k; the ground's as is.
  place(body, p, k) {
    if (body === null) return p;
    const b = this.frames.bodies[body];
    const r = qRotate([b.q[0][k], b.q[1][k], b.q[2][k], b.q[3][k]], p);
    return [b.x[k] + r[0], b.y[k] + r[1], b.z[k] + r[2]];
  }

  update(k) {
    const xs = [];
    const ys = [];
    const zs = [];
    const push = (pts) => {
      xs.push(pts.map((p) => (p ? p[0] : null)));
      ys.push(pts.map((p) => (p ? p[1] : null)));
      zs.push(pts.map((p) => (p ? p[2] : null)));
    };
    for (const b of this.scene.bodies) push(b.sticks.map((p) => this.place(b.name, p, k)));
    const L = this.scene.triad;
    for (let a = 0; a < 3; a++) {
      const pts = [];
      const tip = [0, 0, 0];
      tip[a] = L;
      for (const b of this.scene.bodies) pts.push(this.place(b.name, [0, 0, 0], k), this.place(b.name, tip, k), null);
      push(pts);
    }
    push(this.scene.joints.map((j) => this.place(j.body, j.point, k)));
    const m = this.scene.magnify;
    const colours = [];
    push(this.scene.clearances.map((c) => {
      const j = this.frames.joints[c.joint];
      colours.push(j.mode[k]);
      const e = [m * (j.ex[k] || 0), m * (j.ey[k] || 0), m * (j.ez[k] || 0)];
      return this.place(c.bearing_body, [c.point[0] + e[0], c.point[1] + e[1], c.point[2] + e[2]], k);
    }));
    push(this.scene.markers.map((mk) => this.place(mk.body, mk.point, k)));
    return Plotly.restyle(this.div, { x: xs, y: ys, z: zs }, this.dynamic).then(() =>
      Plotly.restyle(this.div, { "marker.color": [colours] }, [this.dynamic.length - 2])
    );
  }
}

// Points of a sphere (no axis) or a cylinder about `axis` of radius r, from station
// lo to hi, as a plotly surface.
function clearanceSurface(r, axis, lo, hi) {
  const n = 32;
  const xs = [];
  const ys = [];
  const zs = [];
  let p = [1, 0, 0];
  let q = [0, 1, 0];
  if (axis) {
    const a = axis;
    const t = Math.abs(a[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
    const cross = (u, v) => [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    p = cross(a, t);
    const np = Math.hypot(...p);
    p = p.map((v) => v / np);
    q = cross(a, p);
  }
  const rows = axis ? 2 : n / 2 + 1;
  for (let i = 0; i < rows; i++) {
    const rx = [];
    const ry = [];
    const rz = [];
    for (let j = 0; j <= n; j++) {
      const u = (2 * Math.PI * j) / n;
      let v;
      if (axis) {
        const s = i === 0 ? lo : hi;
        v = [0, 1, 2].map((c) => r * (Math.cos(u) * p[c] + Math.sin(u) * q[c]) + s * axis[c]);
      } else {
        const w = (Math.PI * i) / (rows - 1);
        v = [r * Math.sin(w) * Math.cos(u), r * Math.sin(w) * Math.sin(u), r * Math.cos(w)];
      }
      rx.push(v[0]);
      ry.push(v[1]);
      rz.push(v[2]);
    }
    xs.push(rx);
    ys.push(ry);
    zs.push(rz);
  }
  return { type: "surface", x: xs, y: ys, z: zs, opacity: 0.18, showscale: false, hoverinfo: "skip", colorscale: [[0, "#888"], [1, "#888"]], name: "clearance", showlegend: true };
}

class Orbit3D extends View3D {
  constructor(parent, orbit, frames) {
    const box = el("div", { class: "jg-orbit", "data-joint": orbit.joint }, parent);
    el("h3", {}, box, `${orbit.joint}: ${orbit.axis ? "journal" : "ball"} centre [µm]`);
    const div = el("div", { id: "orbit-" + cssId(orbit.joint), class: "jg-orbit-3d" }, box);
    const um = 1e6;
    const ex = orbit.ex.map((v) => (v === null ? null : v * um));
    const ey = orbit.ey.map((v) => (v === null ? null : v * um));
    const ez = orbit.ez.map((v) => (v === null ? null : v * um));
    const c = orbit.clearance * um;
    let lo = -c;
    let hi = c;
    if (orbit.axis) {
      for (let i = 0; i < ex.length; i++) {
        if (ex[i] === null) continue;
        const s = ex[i] * orbit.axis[0] + ey[i] * orbit.axis[1] + ez[i] * orbit.axis[2];
        lo = Math.min(lo, s);
        hi = Math.max(hi, s);
      }
    }
    const surface = clearanceSurface(c, orbit.axis, lo, hi);
    const extent = [[surface.x.flat(), ex], [surface.y.flat(), ey], [surface.z.flat(), ez]].map((parts) =>
      parts.flat().reduce(([a, b], x) => (x === null ? [a, b] : [Math.min(a, x), Math.max(b, x)]), [Infinity, -Infinity])
    );
    const traces = [
      surface,
      { type: "scatter3d", mode: "lines", name: "orbit", x: ex, y: ey, z: ez, line: { width: 3, color: orbit.mode, cmin: 0, cmax: 2, colorscale: MODE_SCALE } },
      { type: "scatter3d", mode: "markers", name: "now", x: [0], y: [0], z: [0], marker: { size: 6, color: [0], cmin: 0, cmax: 2, colorscale: MODE_SCALE, line: { color: "#111", width: 1 } } },
    ];
    super(div, traces, scene3d(" [µm]", extent.map((v) => v[0]), extent.map((v) => v[1])));
    this.orbit = orbit;
    this.frames = frames.joints[orbit.joint];
    const legend = el("div", { class: "jg-mode-legend" }, box);
    MODE_NAMES.forEach((name, k) => {
      const item = el("span", {}, legend);
      el("span", { class: "jg-swatch" }, item).style.borderColor = MODE_COLOURS[k];
      item.appendChild(document.createTextNode(name));
    });
    const shape = orbit.axis ? `cylinder about the axis (${orbit.axis.map((v) => jgFormat(v)).join(", ")})` : "sphere";
    el("p", { class: "jg-note" }, box, `bearing frame${orbit.bearing_body ? " (" + orbit.bearing_body + ")" : " (ground)"}; grey: the clearance ${shape}, radius ${jgFormat(c)} µm${orbit.thinned ? `; drawn through ${orbit.ex.length} of ${orbit.thinned} samples, evenly along the path` : ""}`);
    this.readout = el("p", { class: "jg-readout" }, box, "");
  }

  update(k) {
    const f = this.frames;
    const um = 1e6;
    const e = [(f.ex[k] || 0) * um, (f.ey[k] || 0) * um, (f.ez[k] || 0) * um];
    this.readout.textContent = `|e| = ${Math.hypot(...e).toFixed(1)} µm, ${MODE_NAMES[f.mode[k]] || "-"}`;
    return Plotly.restyle(this.div, { x: [[e[0]]], y: [[e[1]]], z: [[e[2]]], "marker.color": [[f.mode[k]]] }, [2]);
  }
}

function renderSpatialRun(run) {
  const mech = section("mechanism-section", "Mechanism in 3D");
  const grid = el("div", { class: run.orbits.length ? "jg-grid" : "jg-grid jg-single" }, mech);
  const left = el("div", { class: "jg-anim" }, grid);
  const right = el("div", { class: "jg-orbits", id: "orbits" }, grid);
  const mechanism = new Mechanism3D(left, run);
  const views = [mechanism, ...run.orbits.map((o) => new Orbit3D(right, o, run.frames))];
  const plotsSection = section("plots-section", "Channels");
  el("p", { class: "jg-note" }, plotsSection,
    "wheel: zoom in time (shift+wheel: values) · drag: pan · shift+drag: zoom to a box · double-click: reset · click: move the animation there" +
      (run.impacts.length ? " · orange lines: impact onsets" : ""));
  const p = new Player(left, run, views);
  const plots = plotGroup(plotsSection, run.plots, run.impacts.map((i) => i.t), (t) => p.seek(t), run.times);
  views.push({ show: (k, t) => plots.forEach((pl) => pl.setCursor(t)) });
  el("p", { class: "jg-note", id: "magnify-note" }, left,
    "drag: rotate · wheel: zoom · the mode bar: pan, reset" +
      (run.scene.clearances.length ? `; pins drawn at the bearing centre plus ${jgFormat(run.scene.magnify)} times the eccentricity, coloured blue free flight, red impact, green continuous contact` : ""));
  for (const note of run.scene.notes) el("p", { class: "jg-warning jg-frame-note" }, left, note);
  p.ready = Promise.all(views.filter((v) => v.ready).map((v) => v.ready));
  return p;
}

// ------------------------------------------------------------------------ sections

// specs' series may name a shared array of `times` as their x ("run", "ideal").
function plotGroup(parent, specs, markerTimes, onPick, times) {
  const group = new JGPlotGroup();
  const plots = specs.map((spec) => {
    const series = spec.series.map((s) => (typeof s.x === "string" ? Object.assign({}, s, { x: times[s.x] }) : s));
    const s = Object.assign({}, spec, { series, markerTimes: spec.markers ? markerTimes : [] });
    const p = new JGPlot(parent, s, { onPick: spec.time ? onPick : null, height: spec.height });
    if (spec.time) group.add(p);
    return p;
  });
  return plots;
}

function renderRun(run) {
  const mech = section("mechanism-section", "Mechanism");
  const grid = el("div", { class: run.orbits.length ? "jg-grid" : "jg-grid jg-single" }, mech);
  const left = el("div", { class: "jg-anim" }, grid);
  const right = el("div", { class: "jg-orbits", id: "orbits" }, grid);
  const mechanism = new Mechanism(left, run);
  const views = [mechanism];
  const orbits = run.orbits.map((o) => new Orbit(right, o, run.frames));
  views.push(...orbits);
  const plotsSection = section("plots-section", "Channels");
  el("p", { class: "jg-note" }, plotsSection,
    "wheel: zoom in time (shift+wheel: values) · drag: pan · shift+drag: zoom to a box · double-click: reset · click: move the animation there" +
      (run.impacts.length ? " · orange lines: impact onsets (ticks along the top where more than one per 6 pixels)" : ""));
  const markerTimes = run.impacts.map((i) => i.t);
  const p = new Player(left, run, views);
  const plots = plotGroup(plotsSection, run.plots, markerTimes, (t) => p.seek(t), run.times);
  const cursorView = { show: (k, t) => plots.forEach((pl) => pl.setCursor(t)) };
  views.push(cursorView);
  const notes = el("p", { class: "jg-note", id: "magnify-note" }, left, "");
  if (run.scene.clearances.length) {
    notes.textContent = `clearances drawn ${jgFormat(run.scene.magnify)} times larger than they are; journal colour: blue free flight, red impact, green continuous contact; wheel zooms, drag pans, double-click resets`;
  }
  if (run.frames.ideal) {
    const label = el("label", { class: "jg-check" }, left);
    const box = el("input", { type: "checkbox", id: "show-ideal" }, label);
    box.checked = true;
    label.appendChild(document.createTextNode(" ideal run as a grey ghost"));
    box.addEventListener("change", () => mechanism.setGhost(box.checked));
  }
  return p;
}

function renderTables(parent, tables, onSeek) {
  const wrap = el("div", { class: "jg-tables" }, parent);
  for (const t of tables) {
    const node = renderTable(wrap, t, onSeek);
    node._onSeek = onSeek;
  }
}

function renderComparison(cmp, onSeek) {
  const s = section("comparison-section", cmp.title);
  if (cmp.note) el("p", { class: "jg-note" }, s, cmp.note);
  const plots = plotGroup(s, cmp.plots, [], onSeek);
  renderTables(s, cmp.tables, onSeek);
  return plots.filter((p, k) => cmp.plots[k].time);
}

function renderStudy(study) {
  const s = section("study-section", "Study");
  renderTables(s, study.tables, null);
  if (study.plots.length) {
    el("h3", {}, s, "Metrics against parameters");
    el("p", { class: "jg-note" }, s, "hover a point for its case; wheel and drag zoom and pan");
    const grid = el("div", { class: "jg-plot-grid" }, s);
    plotGroup(grid, study.plots, [], null);
  }
  const cases = section("cases-section", "Cases");
  renderTables(cases, [study.cases], null);
  if (study.figures.length) {
    const f = section("figures-section", "Figures");
    for (const fig of study.figures) {
      const fg = el("figure", { class: "jg-figure" }, f);
      el("img", { src: fig.src, alt: fig.name }, fg);
      el("figcaption", {}, fg, fig.name);
    }
  }
}

// ------------------------------------------------------------------------ page

function main() {
  const data = JSON.parse(document.getElementById("jg-data").textContent);
  document.getElementById("title").textContent = data.title;
  document.getElementById("subtitle").textContent = data.subtitle || "";
  let player = null;
  if (data.run) {
    if (data.run.status !== "finished") {
      const warn = el("p", { class: "jg-warning" }, document.getElementById("report"), `the run ${data.run.message || "failed"}: everything shown stops there`);
      warn.id = "run-failed";
    }
    player = data.run.spatial ? renderSpatialRun(data.run) : renderRun(data.run);
  }
  const seek = player ? (t) => player.seek(t) : null;
  if (data.comparison) {
    const plots = renderComparison(data.comparison, seek);
    if (player) player.views.push({ show: (k, t) => plots.forEach((pl) => pl.setCursor(t)) });
  }
  if (data.run) renderTables(section("summary-section", "Summary"), data.run.tables, seek);
  if (data.study) renderStudy(data.study);
  if (player) player.showFrame(0);
  window.jointgapReport = { data, player };
  // A 3D view is ready when plotly has drawn it.
  Promise.resolve(player && player.ready).then(() => (document.body.dataset.ready = "true"));
}

main();
