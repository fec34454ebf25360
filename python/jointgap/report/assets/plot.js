// jointgap report: interactive canvas plots (no library, works offline).
// A plot draws line or scatter series on a canvas; wheel zooms (shift+wheel: y),
// dragging pans, shift+drag zooms to a box, double-click resets, hovering shows the
// values, a click reports its x (the report moves the animation there). Plots of one
// group share their x range; a cursor (a DOM element, class jg-cursor) marks a time.
"use strict";

const JG_COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2"];
const JG_MARGIN = { left: 66, right: 14, top: 8, bottom: 34 };

function jgNiceTicks(lo, hi, count) {
  const span = hi - lo;
  if (!(span > 0) || !isFinite(span)) return [lo];
  const raw = span / Math.max(1, count);
  const power = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 2.5, 5, 10].map((m) => m * power).find((s) => s >= raw) || 10 * power;
  const ticks = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) {
    ticks.push(Math.abs(v) < step * 1e-9 ? 0 : v);
  }
  return ticks;
}

function jgFormat(v, digits) {
  if (v === null || v === undefined || Number.isNaN(v)) return "-";
  if (typeof v !== "number") return String(v);
  if (Number.isInteger(v) && Math.abs(v) < 1e9) return String(v);
  const d = digits || 5;
  const a = Math.abs(v);
  if (a !== 0 && (a < 1e-4 || a >= 1e7)) return v.toExponential(d - 1).replace(/\.?0+e/, "e");
  return String(Number(v.toPrecision(d)));
}

function jgTickText(v, step) {
  const a = Math.max(Math.abs(v), Math.abs(step));
  if (a !== 0 && (a < 1e-3 || a >= 1e6)) return v === 0 ? "0" : v.toExponential(2).replace(/\.?0+e/, "e");
  let decimals = 0;
  while (decimals < 10 && Math.abs(Math.round(step * 10 ** decimals) - step * 10 ** decimals) > 1e-6 * step * 10 ** decimals) decimals++;
  return v.toFixed(decimals);
}

// The first index i with xs[i] >= x (xs ascending, nulls not allowed in x).
function jgLowerBound(xs, x) {
  let lo = 0;
  let hi = xs.length;
  while (lo < hi) {
    const mid = (lo + hi) >> 1;
    if (xs[mid] < x) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

class JGPlotGroup {
  constructor() {
    this.plots = [];
  }
  add(plot) {
    this.plots.push(plot);
    plot.group = this;
  }
  setXRange(x0, x1, source) {
    for (const p of this.plots) if (p !== source) p.setXRange(x0, x1, true);
  }
  reset(source) {
    for (const p of this.plots) if (p !== source) p.resetView(true);
  }
}

class JGPlot {
  // spec: {id, title, xlabel, ylabel, kind: "line"|"scatter", series: [{label, x, y,
  // dash, names}], markers: [x...]}; options: {onPick(x), height}
  constructor(container, spec, options) {
    this.spec = spec;
    this.options = options || {};
    this.group = null;
    this.series = spec.series.map((s, k) => ({
      ...s,
      colour: s.dash ? "#222" : s.colour || JG_COLOURS[k % JG_COLOURS.length],
    }));
    this.markers = spec.markerTimes || [];
    this.full = this._extent();
    this.view = { x0: this.full.x0, x1: this.full.x1, y0: null, y1: null };
    this.cursorX = null;
    this._build(container);
    this.draw();
  }

  _extent() {
    let x0 = Infinity;
    let x1 = -Infinity;
    let y0 = Infinity;
    let y1 = -Infinity;
    for (const s of this.series) {
      for (let i = 0; i < s.x.length; i++) {
        const x = s.x[i];
        const y = s.y[i];
        if (x === null || y === null) continue;
        if (x < x0) x0 = x;
        if (x > x1) x1 = x;
        if (y < y0) y0 = y;
        if (y > y1) y1 = y;
      }
    }
    if (!isFinite(x0)) return { x0: 0, x1: 1, y0: 0, y1: 1 };
    if (x1 === x0) {
      const d = Math.abs(x0) > 0 ? 0.1 * Math.abs(x0) : 0.5;
      x0 -= d;
      x1 += d;
    } else if (this.spec.kind === "scatter") {
      const pad = 0.05 * (x1 - x0); // points on the edge stay whole
      x0 -= pad;
      x1 += pad;
    }
    return { x0, x1, y0, y1 };
  }

  _build(container) {
    const root = document.createElement("div");
    root.className = "jg-plot";
    if (this.spec.id) root.dataset.plot = this.spec.id;
    const head = document.createElement("div");
    head.className = "jg-plot-head";
    const title = document.createElement("span");
    title.className = "jg-plot-title";
    title.textContent = this.spec.title || "";
    head.appendChild(title);
    const legend = document.createElement("span");
    legend.className = "jg-legend";
    if (this.series.length > 1) {
      for (const s of this.series) {
        const item = document.createElement("span");
        item.className = "jg-legend-item";
        const swatch = document.createElement("span");
        swatch.className = "jg-swatch" + (s.dash ? " dashed" : "");
        swatch.style.borderColor = s.colour;
        item.appendChild(swatch);
        item.appendChild(document.createTextNode(s.label));
        legend.appendChild(item);
      }
    }
    head.appendChild(legend);
    const reset = document.createElement("button");
    reset.type = "button";
    reset.className = "jg-small";
    reset.textContent = "reset zoom";
    reset.addEventListener("click", () => this.resetView());
    head.appendChild(reset);
    root.appendChild(head);

    const area = document.createElement("div");
    area.className = "jg-plot-area";
    area.style.height = (this.options.height || 170) + "px";
    this.canvas = document.createElement("canvas");
    area.appendChild(this.canvas);
    this.cursor = document.createElement("div");
    this.cursor.className = "jg-cursor";
    this.cursor.style.display = "none";
    area.appendChild(this.cursor);
    this.box = document.createElement("div");
    this.box.className = "jg-box";
    this.box.style.display = "none";
    area.appendChild(this.box);
    this.tip = document.createElement("div");
    this.tip.className = "jg-tip";
    this.tip.style.display = "none";
    area.appendChild(this.tip);
    this.dots = this.series.map((s) => {
      const d = document.createElement("div");
      d.className = "jg-dot";
      d.style.background = s.colour;
      d.style.display = "none";
      area.appendChild(d);
      return d;
    });
    root.appendChild(area);
    container.appendChild(root);
    this.root = root;
    this.area = area;
    this._listen();
    if (typeof ResizeObserver !== "undefined") {
      new ResizeObserver(() => this.draw()).observe(area);
    }
  }

  // ---------------------------------------------------------------- geometry

  _size() {
    const w = this.area.clientWidth;
    const h = this.area.clientHeight;
    return { w, h, pw: Math.max(10, w - JG_MARGIN.left - JG_MARGIN.right), ph: Math.max(10, h - JG_MARGIN.top - JG_MARGIN.bottom) };
  }

  _yRange() {
    if (this.view.y0 !== null) return [this.view.y0, this.view.y1];
    let lo = Infinity;
    let hi = -Infinity;
    for (const s of this.series) {
      const a = Math.max(0, jgLowerBound(s.x, this.view.x0) - 1);
      const b = Math.min(s.x.length, jgLowerBound(s.x, this.view.x1) + 1);
      for (let i = a; i < b; i++) {
        const y = s.y[i];
        if (y === null) continue;
        if (y < lo) lo = y;
        if (y > hi) hi = y;
      }
    }
    if (!isFinite(lo)) return [0, 1];
    if (hi === lo) {
      const d = Math.abs(hi) > 0 ? Math.abs(hi) * 0.1 : 1;
      return [lo - d, hi + d];
    }
    const pad = 0.05 * (hi - lo);
    return [lo - pad, hi + pad];
  }

  xToPixel(x) {
    const { pw } = this._size();
    return JG_MARGIN.left + ((x - this.view.x0) / (this.view.x1 - this.view.x0)) * pw;
  }

  pixelToX(px) {
    const { pw } = this._size();
    return this.view.x0 + ((px - JG_MARGIN.left) / pw) * (this.view.x1 - this.view.x0);
  }

  // ---------------------------------------------------------------- drawing

  draw() {
    const { w, h, pw, ph } = this._size();
    if (w === 0 || h === 0) return;
    const dpr = window.devicePixelRatio || 1;
    if (this.canvas.width !== Math.round(w * dpr) || this.canvas.height !== Math.round(h * dpr)) {
      this.canvas.width = Math.round(w * dpr);
      this.canvas.height = Math.round(h * dpr);
      this.canvas.style.width = w + "px";
      this.canvas.style.height = h + "px";
    }
    const ctx = this.canvas.getContext("2d");
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, w, h);
    const [y0, y1] = this._yRange();
    this._yr = [y0, y1];
    const X = (x) => JG_MARGIN.left + ((x - this.view.x0) / (this.view.x1 - this.view.x0)) * pw;
    const Y = (y) => JG_MARGIN.top + (1 - (y - y0) / (y1 - y0)) * ph;
    this._axes(ctx, X, Y, y0, y1, w, h, pw, ph);
    ctx.save();
    ctx.beginPath();
    ctx.rect(JG_MARGIN.left, JG_MARGIN.top, pw, ph);
    ctx.clip();
    if (this.markers.length) {
      // Many impacts in view (more than one per 6 pixels) would paint the plot orange:
      // they become ticks along its top edge until a zoom spreads them out.
      const seen = this.markers.filter((m) => m >= this.view.x0 && m <= this.view.x1);
      const ticks = seen.length > pw / 6;
      ctx.strokeStyle = "rgba(230, 120, 0, 0.35)";
      ctx.lineWidth = 1;
      ctx.beginPath();
      for (const m of seen) {
        const px = Math.round(X(m)) + 0.5;
        ctx.moveTo(px, JG_MARGIN.top);
        ctx.lineTo(px, JG_MARGIN.top + (ticks ? 6 : ph));
      }
      ctx.stroke();
    }
    for (const s of this.series) {
      if (this.spec.kind === "scatter") this._scatter(ctx, s, X, Y);
      else this._line(ctx, s, X, Y, pw);
    }
    ctx.restore();
    this._placeCursor();
  }

  _axes(ctx, X, Y, y0, y1, w, h, pw, ph) {
    ctx.font = "11px system-ui, sans-serif";
    ctx.fillStyle = "#333";
    ctx.strokeStyle = "#e3e3e3";
    ctx.lineWidth = 1;
    const xt = jgNiceTicks(this.view.x0, this.view.x1, Math.max(2, Math.floor(pw / 90)));
    const yt = jgNiceTicks(y0, y1, Math.max(2, Math.floor(ph / 40)));
    const xs = xt.length > 1 ? xt[1] - xt[0] : 1;
    const ys = yt.length > 1 ? yt[1] - yt[0] : 1;
    ctx.beginPath();
    for (const t of xt) {
      const px = Math.round(X(t)) + 0.5;
      ctx.moveTo(px, JG_MARGIN.top);
      ctx.lineTo(px, JG_MARGIN.top + ph);
    }
    for (const t of yt) {
      const py = Math.round(Y(t)) + 0.5;
      ctx.moveTo(JG_MARGIN.left, py);
      ctx.lineTo(JG_MARGIN.left + pw, py);
    }
    ctx.stroke();
    ctx.strokeStyle = "#888";
    ctx.strokeRect(JG_MARGIN.left + 0.5, JG_MARGIN.top + 0.5, pw, ph);
    ctx.textAlign = "center";
    ctx.textBaseline = "top";
    for (const t of xt) ctx.fillText(jgTickText(t, xs), X(t), JG_MARGIN.top + ph + 4);
    ctx.fillText(this.spec.xlabel || "", JG_MARGIN.left + pw / 2, h - 13);
    ctx.textAlign = "right";
    ctx.textBaseline = "middle";
    for (const t of yt) ctx.fillText(jgTickText(t, ys), JG_MARGIN.left - 5, Y(t));
    ctx.save();
    ctx.translate(11, JG_MARGIN.top + ph / 2);
    ctx.rotate(-Math.PI / 2);
    ctx.textAlign = "center";
    ctx.fillText(this.spec.ylabel || "", 0, 0);
    ctx.restore();
  }

  // A line; when more than two samples fall on one pixel column, the column's first,
  // smallest, largest and last values are drawn, so no peak is lost.
  _line(ctx, s, X, Y, pw) {
    const a = Math.max(0, jgLowerBound(s.x, this.view.x0) - 1);
    const b = Math.min(s.x.length, jgLowerBound(s.x, this.view.x1) + 1);
    ctx.strokeStyle = s.colour;
    ctx.lineWidth = s.dash ? 1.3 : 1.1;
    ctx.setLineDash(s.dash ? [5, 4] : []);
    ctx.beginPath();
    const dense = b - a > 3 * pw;
    let pen = false;
    let col = null;
    let first = 0;
    let lo = 0;
    let hi = 0;
    let last = 0;
    const flush = () => {
      if (col === null) return;
      if (!pen) ctx.moveTo(col, Y(first));
      else ctx.lineTo(col, Y(first));
      ctx.lineTo(col, Y(lo));
      ctx.lineTo(col, Y(hi));
      ctx.lineTo(col, Y(last));
      pen = true;
    };
    for (let i = a; i < b; i++) {
      const y = s.y[i];
      if (y === null) {
        flush();
        col = null;
        pen = false;
        continue;
      }
      const px = X(s.x[i]);
      if (!dense) {
        if (pen) ctx.lineTo(px, Y(y));
        else ctx.moveTo(px, Y(y));
        pen = true;
        continue;
      }
      const c = Math.round(px);
      if (c !== col) {
        flush();
        col = c;
        first = lo = hi = last = y;
      } else {
        if (y < lo) lo = y;
        if (y > hi) hi = y;
        last = y;
      }
    }
    if (dense) flush();
    ctx.stroke();
    ctx.setLineDash([]);
  }

  _scatter(ctx, s, X, Y) {
    ctx.fillStyle = s.colour;
    for (let i = 0; i < s.x.length; i++) {
      if (s.x[i] === null || s.y[i] === null) continue;
      ctx.beginPath();
      ctx.arc(X(s.x[i]), Y(s.y[i]), 3.5, 0, 2 * Math.PI);
      ctx.fill();
    }
  }

  // ---------------------------------------------------------------- cursor and view

  setCursor(x) {
    this.cursorX = x;
    this._placeCursor();
  }

  _placeCursor() {
    if (this.cursorX === null || this.cursorX < this.view.x0 || this.cursorX > this.view.x1) {
      this.cursor.style.display = "none";
      return;
    }
    const { ph } = this._size();
    this.cursor.style.display = "block";
    this.cursor.style.left = this.xToPixel(this.cursorX).toFixed(1) + "px";
    this.cursor.style.top = JG_MARGIN.top + "px";
    this.cursor.style.height = ph + "px";
  }

  setXRange(x0, x1, fromGroup) {
    if (!(x1 > x0)) return;
    this.view.x0 = x0;
    this.view.x1 = x1;
    this.draw();
    if (!fromGroup && this.group) this.group.setXRange(x0, x1, this);
  }

  resetView(fromGroup) {
    this.view = { x0: this.full.x0, x1: this.full.x1, y0: null, y1: null };
    this.draw();
    if (!fromGroup && this.group) this.group.reset(this);
  }

  _zoomX(px, factor) {
    const x = this.pixelToX(px);
    let x0 = x - (x - this.view.x0) * factor;
    let x1 = x + (this.view.x1 - x) * factor;
    const span = this.full.x1 - this.full.x0;
    if (x1 - x0 > span) {
      x0 = this.full.x0;
      x1 = this.full.x1;
    }
    if (x1 - x0 < span * 1e-7) return;
    this.setXRange(x0, x1);
  }

  _zoomY(py, factor) {
    const [y0, y1] = this.view.y0 !== null ? [this.view.y0, this.view.y1] : this._yr;
    const { ph } = this._size();
    const y = y1 - ((py - JG_MARGIN.top) / ph) * (y1 - y0);
    this.view.y0 = y - (y - y0) * factor;
    this.view.y1 = y + (y1 - y) * factor;
    this.draw();
  }

  // ---------------------------------------------------------------- events

  _listen() {
    const area = this.area;
    let drag = null;
    area.addEventListener(
      "wheel",
      (e) => {
        e.preventDefault();
        const r = area.getBoundingClientRect();
        const factor = Math.pow(1.0015, e.deltaY);
        if (e.shiftKey) this._zoomY(e.clientY - r.top, factor);
        else this._zoomX(e.clientX - r.left, factor);
      },
      { passive: false }
    );
    area.addEventListener("pointerdown", (e) => {
      const r = area.getBoundingClientRect();
      drag = { x: e.clientX - r.left, y: e.clientY - r.top, view: { ...this.view }, box: e.shiftKey, moved: false };
      area.setPointerCapture(e.pointerId);
    });
    area.addEventListener("pointermove", (e) => {
      const r = area.getBoundingClientRect();
      const px = e.clientX - r.left;
      const py = e.clientY - r.top;
      if (!drag) {
        this._hover(px, py);
        return;
      }
      if (Math.abs(px - drag.x) + Math.abs(py - drag.y) > 3) drag.moved = true;
      if (!drag.moved) return;
      this._hideHover();
      if (drag.box) {
        const { ph } = this._size();
        this.box.style.display = "block";
        this.box.style.left = Math.min(px, drag.x) + "px";
        this.box.style.width = Math.abs(px - drag.x) + "px";
        this.box.style.top = JG_MARGIN.top + "px";
        this.box.style.height = ph + "px";
        return;
      }
      const { pw, ph } = this._size();
      const dx = ((px - drag.x) / pw) * (drag.view.x1 - drag.view.x0);
      if (drag.view.y0 !== null) {
        const dy = ((py - drag.y) / ph) * (drag.view.y1 - drag.view.y0);
        this.view.y0 = drag.view.y0 + dy;
        this.view.y1 = drag.view.y1 + dy;
      }
      this.setXRange(drag.view.x0 - dx, drag.view.x1 - dx);
    });
    const end = (e) => {
      if (!drag) return;
      const r = area.getBoundingClientRect();
      const px = e.clientX - r.left;
      if (drag.box && drag.moved) {
        this.box.style.display = "none";
        const a = this.pixelToX(Math.min(px, drag.x));
        const b = this.pixelToX(Math.max(px, drag.x));
        this.setXRange(a, b);
      } else if (!drag.moved && this.options.onPick) {
        this.options.onPick(this.pixelToX(px));
      }
      drag = null;
    };
    area.addEventListener("pointerup", end);
    area.addEventListener("pointercancel", () => {
      drag = null;
      this.box.style.display = "none";
    });
    area.addEventListener("pointerleave", () => this._hideHover());
    area.addEventListener("dblclick", () => this.resetView());
  }

  _hideHover() {
    this.tip.style.display = "none";
    for (const d of this.dots) d.style.display = "none";
  }

  _hover(px, py) {
    const { pw, ph } = this._size();
    if (px < JG_MARGIN.left || px > JG_MARGIN.left + pw || py < JG_MARGIN.top || py > JG_MARGIN.top + ph) {
      this._hideHover();
      return;
    }
    const [y0, y1] = this._yr;
    const Y = (y) => JG_MARGIN.top + (1 - (y - y0) / (y1 - y0)) * ph;
    const lines = [];
    if (this.spec.kind === "scatter") {
      let best = null;
      this.series.forEach((s, k) => {
        for (let i = 0; i < s.x.length; i++) {
          if (s.x[i] === null || s.y[i] === null) continue;
          const d = Math.hypot(this.xToPixel(s.x[i]) - px, Y(s.y[i]) - py);
          if (best === null || d < best.d) best = { d, k, i };
        }
      });
      this.dots.forEach((d) => (d.style.display = "none"));
      if (best === null || best.d > 25) {
        this.tip.style.display = "none";
        return;
      }
      const s = this.series[best.k];
      const dot = this.dots[best.k];
      dot.style.display = "block";
      dot.style.left = this.xToPixel(s.x[best.i]) + "px";
      dot.style.top = Y(s.y[best.i]) + "px";
      if (s.names) lines.push(String(s.names[best.i]));
      lines.push(`${this.spec.xlabel}: ${jgFormat(s.x[best.i])}`);
      lines.push(`${this.spec.ylabel}: ${jgFormat(s.y[best.i])}`);
    } else {
      const x = this.pixelToX(px);
      lines.push(`${this.spec.xlabel || "x"} = ${jgFormat(x, 6)}`);
      this.series.forEach((s, k) => {
        const dot = this.dots[k];
        let i = jgLowerBound(s.x, x);
        if (i > 0 && (i === s.x.length || x - s.x[i - 1] < s.x[i] - x)) i -= 1;
        if (i >= s.x.length || s.y[i] === null) {
          dot.style.display = "none";
          return;
        }
        dot.style.display = "block";
        dot.style.left = this.xToPixel(s.x[i]) + "px";
        dot.style.top = Math.min(Math.max(Y(s.y[i]), JG_MARGIN.top), JG_MARGIN.top + ph) + "px";
        lines.push(`${s.label}: ${jgFormat(s.y[i])}`);
      });
    }
    this.tip.textContent = lines.join("\n");
    this.tip.style.display = "block";
    const right = px > JG_MARGIN.left + pw * 0.6;
    this.tip.style.left = right ? "" : px + 12 + "px";
    this.tip.style.right = right ? this.area.clientWidth - px + 12 + "px" : "";
    this.tip.style.top = Math.max(JG_MARGIN.top, py - 10) + "px";
  }
}
