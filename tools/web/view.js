// SPDX-License-Identifier: MIT
// Draws the model (model.js): OM and TM each kept as an image of one pixel per cell (the
// exported map's greys: 0 occupied, 254 free, 205 unknown; TM's visit counts), scaled onto
// a canvas with the path, the robot, its current sweep and a scale bar.
"use strict";
(function (sv) {
  const M = sv.model;
  const UNKNOWN = sv.tables.map.unknown;
  const SWEEP_TICKS = 100; // a reading older than this (1 s) is no longer the current sweep

  /** An a×b canvas holding one map at one pixel per cell, the first row the grid's last. */
  class Layer {
    constructor() {
      this.canvas = document.createElement("canvas");
      this.canvas.width = this.canvas.height = 1;
      this.ctx = this.canvas.getContext("2d", {willReadFrequently: true});
    }

    size(a, b) {
      if (this.canvas.width !== a || this.canvas.height !== b) {
        this.canvas.width = a;
        this.canvas.height = b;
      }
    }

    /** Cells [first, first + n) of grid row `row`, their greys from grey(index). */
    paint(row, first, n, b, a, grey) {
      const img = this.ctx.createImageData(n, 1);
      const d = img.data;
      for (let k = 0; k < n; k++) {
        const v = grey(row * a + first + k);
        d[4 * k] = d[4 * k + 1] = d[4 * k + 2] = v;
        d[4 * k + 3] = 255;
      }
      this.ctx.putImageData(img, first, b - 1 - row);
    }

    /** The greys of the layer, a·b bytes, first row the grid's last (what a test reads). */
    greys() {
      const w = this.canvas.width;
      const h = this.canvas.height;
      const d = this.ctx.getImageData(0, 0, w, h).data;
      const out = new Uint8Array(w * h);
      for (let i = 0; i < w * h; i++) {
        out[i] = d[4 * i];
      }
      return out;
    }
  }

  /** A length for the scale bar: 1, 2 or 5 times a power of ten, near `m` metres. */
  function niceLength(m) {
    const p = Math.pow(10, Math.floor(Math.log10(m)));
    for (const f of [5, 2, 1]) {
      if (f * p <= m) {
        return f * p;
      }
    }
    return p;
  }

  class View {
    constructor(model, omCanvas, tmCanvas) {
      this.model = model;
      this.canvases = {om: omCanvas, tm: tmCanvas};
      this.layers = {om: new Layer(), tm: new Layer()};
      this.known = null; // the cells drawn known so far: [minA, maxA, minB, maxB]
      this.dirty = true;
      this.pending = false;
      model.listen((what, d) => this.changed(what, d));
    }

    changed(what, d) {
      const m = this.model;
      if (what === "reset") {
        this.known = null;
        this.layers.om.size(1, 1);
        this.layers.tm.size(1, 1);
      } else if (what === "hello") {
        const g = m.geo;
        const resized = this.layers.om.canvas.width !== g.a || this.layers.om.canvas.height !== g.b;
        if (resized || this.mode !== g.om_mode || this.tmMax !== g.tm_max) {
          this.layers.om.size(g.a, g.b);
          this.layers.tm.size(g.a, g.b);
          this.mode = g.om_mode;
          this.tmMax = g.tm_max;
          this.known = null;
          for (let r = 0; r < g.b; r++) {
            this.paintRow(0, r, 0, g.a);
            this.paintRow(1, r, 0, g.a);
          }
        }
      } else if (what === "row") {
        this.paintRow(d.map, d.row, d.first, d.n);
        // In the paper's hit-count mode a cell TM has visited is free: TM paints OM too.
        if (d.map === 1 && m.geo.om_mode !== sv.tables.map.omEvidence) {
          this.paintRow(0, d.row, d.first, d.n);
        }
      }
      this.request();
    }

    paintRow(map, row, first, n) {
      const m = this.model;
      const g = m.geo;
      if (map === 0) {
        this.layers.om.paint(row, first, n, g.b, g.a, (i) => {
          const v = m.cell(i);
          if (v !== UNKNOWN) {
            this.extend(i % g.a, row);
          }
          return v;
        });
      } else {
        this.layers.tm.paint(row, first, n, g.b, g.a, (i) => M.countGrey(m.tm[i], g.tm_max));
      }
    }

    extend(a, b) {
      const k = this.known;
      if (k === null) {
        this.known = [a, a, b, b];
      } else {
        k[0] = Math.min(k[0], a);
        k[1] = Math.max(k[1], a);
        k[2] = Math.min(k[2], b);
        k[3] = Math.max(k[3], b);
      }
    }

    /** Redraw at the next frame, at most once a frame however many rows came. */
    request() {
      this.dirty = true;
      if (!this.pending) {
        this.pending = true;
        const go = () => {
          this.pending = false;
          if (this.dirty) {
            this.dirty = false;
            this.draw();
          }
        };
        if (typeof requestAnimationFrame === "function" && !document.hidden) {
          requestAnimationFrame(go);
        } else {
          setTimeout(go, 100);
        }
      }
    }

    /** The world rectangle to show: what is known and the path, with a margin. */
    region() {
      const m = this.model;
      const g = m.geo;
      const cell = g.cell_um * 1e-6;
      const ox = g.origin_x_um * 1e-6;
      const oy = g.origin_y_um * 1e-6;
      let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
      if (this.known !== null) {
        const k = this.known;
        x0 = ox + k[0] * cell;
        x1 = ox + (k[1] + 1) * cell;
        y0 = oy + k[2] * cell;
        y1 = oy + (k[3] + 1) * cell;
      }
      for (const [x, y] of m.path) {
        x0 = Math.min(x0, x);
        x1 = Math.max(x1, x);
        y0 = Math.min(y0, y);
        y1 = Math.max(y1, y);
      }
      if (!isFinite(x0)) {
        return [ox, ox + g.a * cell, oy, oy + g.b * cell];
      }
      const margin = 0.5;
      const min = 3.0;
      const cx = (x0 + x1) / 2;
      const cy = (y0 + y1) / 2;
      const half = Math.max(x1 - x0, y1 - y0, min) / 2 + margin;
      return [cx - half, cx + half, cy - half, cy + half];
    }

    draw() {
      for (const which of ["om", "tm"]) {
        const c = this.canvases[which];
        if (c) {
          this.drawOne(c, which);
        }
      }
    }

    drawOne(canvas, which) {
      const m = this.model;
      const dpr = window.devicePixelRatio || 1;
      const w = Math.max(1, Math.round(canvas.clientWidth * dpr));
      const h = Math.max(1, Math.round(canvas.clientHeight * dpr));
      if (canvas.width !== w || canvas.height !== h) {
        canvas.width = w;
        canvas.height = h;
      }
      const ctx = canvas.getContext("2d");
      ctx.setTransform(1, 0, 0, 1, 0, 0);
      ctx.fillStyle = "#8a8f98";
      ctx.fillRect(0, 0, w, h);
      if (m.geo === null) {
        ctx.fillStyle = "#ffffff";
        ctx.font = Math.round(14 * dpr) + "px sans-serif";
        ctx.fillText("waiting for a HELLO frame (the grid's geometry)", 12 * dpr, 24 * dpr);
        return;
      }
      const g = m.geo;
      const cell = g.cell_um * 1e-6;
      const ox = g.origin_x_um * 1e-6;
      const oy = g.origin_y_um * 1e-6;
      let [x0, x1, y0, y1] = this.region();
      // Square metres on screen: widen the region to the canvas's shape.
      const s = Math.min(w / (x1 - x0), h / (y1 - y0));
      const cx = (x0 + x1) / 2;
      const cy = (y0 + y1) / 2;
      x0 = cx - w / s / 2;
      y1 = cy + h / s / 2;
      const X = (x) => (x - x0) * s;
      const Y = (y) => (y1 - y) * s;
      ctx.imageSmoothingEnabled = false;
      ctx.drawImage(this.layers[which].canvas, X(ox), Y(oy + g.b * cell), g.a * cell * s,
        g.b * cell * s);

      if (m.path.length > 1) {
        // Translucent and thin: the map under the path is what matters.
        ctx.strokeStyle = which === "om" ? "rgba(214, 39, 40, 0.6)" : "rgba(31, 119, 180, 0.45)";
        ctx.lineWidth = (which === "om" ? 1.3 : 1) * dpr;
        ctx.beginPath();
        ctx.moveTo(X(m.path[0][0]), Y(m.path[0][1]));
        for (const [x, y] of m.path) {
          ctx.lineTo(X(x), Y(y));
        }
        ctx.stroke();
      }
      if (which === "om") {
        this.drawSweep(ctx, X, Y, s, dpr);
      }
      if (m.pose !== null) {
        const x = X(m.pose.x_um * 1e-6);
        const y = Y(m.pose.y_um * 1e-6);
        const th = M.wrapRad(m.pose.heading);
        const r = Math.max(0.09 * s, 4 * dpr);
        ctx.fillStyle = "rgba(214, 39, 40, 0.85)";
        ctx.beginPath();
        ctx.arc(x, y, r, 0, 2 * Math.PI);
        ctx.fill();
        ctx.strokeStyle = "#ffffff";
        ctx.lineWidth = 2 * dpr;
        ctx.beginPath();
        ctx.moveTo(x, y);
        ctx.lineTo(x + r * Math.cos(th), y - r * Math.sin(th));
        ctx.stroke();
      }
      this.drawScale(ctx, s, w, h, dpr, cell);
    }

    /** The last reading of each stop, if recent: hits to their echo, the rest to rc. */
    drawSweep(ctx, X, Y, s, dpr) {
      const m = this.model;
      const g = m.geo;
      if (g.mount_x_um === undefined) {
        return;
      }
      const rc = g.confidence_radius_um * 1e-6;
      const yaw = g.mount_yaw_mdeg / 1000 * Math.PI / 180;
      for (const r of m.sweep.values()) {
        if (m.ticks - r.ticks > SWEEP_TICKS) {
          continue;
        }
        const psi = M.wrapRad(r.heading);
        const c = Math.cos(psi);
        const sn = Math.sin(psi);
        const sx = r.x_um * 1e-6 + c * g.mount_x_um * 1e-6 - sn * g.mount_y_um * 1e-6;
        const sy = r.y_um * 1e-6 + sn * g.mount_x_um * 1e-6 + c * g.mount_y_um * 1e-6;
        const th = psi + Math.PI / 2 - r.servo_mdeg / 1000 * Math.PI / 180 + yaw;
        const hit = r.outcome === 0 || r.outcome === 3; // an echo inside rc (3: off the grid)
        const d = hit ? r.range_um * 1e-6 : rc;
        ctx.strokeStyle = hit ? "rgba(255, 127, 14, 0.9)" : "rgba(255, 255, 255, 0.6)";
        ctx.lineWidth = 1.2 * dpr;
        ctx.setLineDash(hit ? [] : [4 * dpr, 4 * dpr]);
        ctx.beginPath();
        ctx.moveTo(X(sx), Y(sy));
        ctx.lineTo(X(sx + d * Math.cos(th)), Y(sy + d * Math.sin(th)));
        ctx.stroke();
        ctx.setLineDash([]);
        if (hit) {
          ctx.fillStyle = "#ff7f0e";
          ctx.beginPath();
          ctx.arc(X(sx + d * Math.cos(th)), Y(sy + d * Math.sin(th)), 3 * dpr, 0, 2 * Math.PI);
          ctx.fill();
        }
      }
    }

    drawScale(ctx, s, w, h, dpr, cell) {
      const len = niceLength(w / s / 4);
      const px = len * s;
      const x = 12 * dpr;
      const y = h - 14 * dpr;
      ctx.font = Math.round(12 * dpr) + "px sans-serif";
      const label = (len >= 1 ? len + " m" : Math.round(len * 1000) + " mm") +
        "  (cells of " + Math.round(cell * 1000) + " mm)";
      const wide = Math.max(px, ctx.measureText(label).width);
      ctx.fillStyle = "rgba(0, 0, 0, 0.55)";
      ctx.fillRect(x - 6 * dpr, y - 24 * dpr, wide + 12 * dpr, 32 * dpr);
      ctx.strokeStyle = "#ffffff";
      ctx.lineWidth = 3 * dpr;
      ctx.beginPath();
      ctx.moveTo(x, y - 6 * dpr);
      ctx.lineTo(x, y);
      ctx.lineTo(x + px, y);
      ctx.lineTo(x + px, y - 6 * dpr);
      ctx.stroke();
      ctx.fillStyle = "#ffffff";
      ctx.fillText(label, x, y - 10 * dpr);
    }
  }

  sv.view = {View, Layer, niceLength};
})(window.slamview = window.slamview || {});
