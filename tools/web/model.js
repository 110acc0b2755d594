// SPDX-License-Identifier: MIT
// What the robot has told the page: the grid's geometry, OM and TM, the path, the current
// sweep, its state and its answers, built from decoded frames (protocol.js); and the map
// files it makes, the same trinary PGM + YAML as the other tools write.
"use strict";
(function (sv) {
  const T = sv.tables;
  const P = sv.protocol;
  const BAM_RAD = 2 * Math.PI / 4294967296;
  const PATH_STEP_UM = 5000; // a new path point once the robot has moved this far

  /** Whole micrometres as metres with six decimals, as the C programs print them. */
  function umText(um) {
    const a = Math.abs(um);
    return (um < 0 ? "-" : "") + Math.floor(a / 1e6) + "." + String(a % 1e6).padStart(6, "0");
  }

  /** The exported value of one cell (slamlink.trinary): occupied, free or unknown. */
  function trinaryCell(mode, om, tm) {
    if (mode === T.map.omEvidence) {
      return om < T.map.evidenceZero ? T.map.free : om > T.map.evidenceZero ? T.map.occupied
        : T.map.unknown;
    }
    return om !== 0 ? T.map.occupied : tm !== 0 ? T.map.free : T.map.unknown;
  }

  /** A count as a grey (slamlink.counts_image): 255 for none, 0 for top and more. */
  function countGrey(v, top) {
    const t = Math.max(top, 1);
    return 255 - Math.floor((Math.min(v, t) * 255 + (t >> 1)) / t);
  }

  /** A binary angle in radians, in [-pi, pi]. */
  function wrapRad(bam) {
    let r = bam * BAM_RAD;
    return r > Math.PI ? r - 2 * Math.PI : r;
  }

  class Model {
    constructor() {
      this.listeners = [];
      this.reset();
    }

    /** Called with (what, detail): "hello", "row" {map, row, first, n}, "frame" fr. */
    listen(fn) {
      this.listeners.push(fn);
    }

    emit(what, detail) {
      for (const fn of this.listeners) {
        fn(what, detail);
      }
    }

    reset() {
      this.geo = null;
      this.om = null;
      this.tm = null;
      this.path = [];          // [x_m, y_m] points
      this.pathAt = null;      // the last point in µm
      this.pathM = 0;          // distance along the path, m
      this.pose = null;        // the last POSE frame
      this.sweep = new Map();  // stop -> its last READING frame
      this.status = null;      // the last STATUS frame
      this.ticks = 0;          // the latest time any frame gave
      this.answers = [];       // {ticks, text, ok} of ACK, ERROR and CONFIG frames
      this.config = {};        // key name -> value text, from CONFIG answers
      this.byType = {};        // frames taken, by type
      this.badRows = 0;        // map rows that do not fit the grid of the last HELLO
      this.passes = 0;         // OM passes that reached the last row
      this.emit("reset");
    }

    take(fr) {
      this.byType[fr.type] = (this.byType[fr.type] || 0) + 1;
      if (fr.ticks !== undefined && fr.ticks > this.ticks) {
        this.ticks = fr.ticks;
      }
      switch (fr.type) {
      case "hello":
        if (this.geo === null || this.geo.a !== fr.a || this.geo.b !== fr.b) {
          // Cells no row has brought yet are unknown: an evidence map's 128, or no hits.
          this.om = new Uint8Array(fr.a * fr.b).fill(
            fr.om_mode === T.map.omEvidence ? T.map.evidenceZero : 0);
          this.tm = new Uint8Array(fr.a * fr.b);
        }
        this.geo = fr;
        this.emit("hello", fr);
        break;
      case "pose":
        this.takePose(fr);
        break;
      case "reading":
        this.sweep.set(fr.stop, fr);
        break;
      case "map_row":
        this.takeRow(fr);
        break;
      case "status":
        this.status = fr;
        break;
      case "ack":
      case "error":
      case "config":
        this.answers.push({ticks: this.ticks, text: P.answerText(fr), ok: fr.type !== "error"});
        if (fr.type === "config") {
          const kv = P.keyValue(fr.key, fr.raw);
          this.config[kv.name] = kv.text;
        }
        break;
      default:
        break;
      }
      this.emit("frame", fr);
    }

    takePose(fr) {
      this.pose = fr;
      const n = this.path.length;
      if (n > 0 && Math.hypot(fr.x_um - this.pathAt[0], fr.y_um - this.pathAt[1]) < PATH_STEP_UM) {
        return;
      }
      const x = fr.x_um * 1e-6;
      const y = fr.y_um * 1e-6;
      if (n > 0) {
        this.pathM += Math.hypot(x - this.path[n - 1][0], y - this.path[n - 1][1]);
      }
      this.path.push([x, y]);
      this.pathAt = [fr.x_um, fr.y_um];
    }

    takeRow(fr) {
      const g = this.geo;
      if (g === null || fr.map > 1 || fr.row >= g.b || fr.first + fr.cells.length > g.a) {
        this.badRows++;
        return;
      }
      (fr.map === 0 ? this.om : this.tm).set(fr.cells, fr.row * g.a + fr.first);
      if (fr.map === 0 && fr.row === g.b - 1 && fr.first + fr.cells.length === g.a) {
        this.passes++;
      }
      this.emit("row", {map: fr.map, row: fr.row, first: fr.first, n: fr.cells.length});
    }

    /** OM's trinary value at a grid index. */
    cell(i) {
      return trinaryCell(this.geo.om_mode, this.om[i], this.tm[i]);
    }

    /** OM as the exported image: a·b bytes, the first row the grid's last. */
    trinaryImage() {
      const g = this.geo;
      const img = new Uint8Array(g.a * g.b);
      for (let r = 0; r < g.b; r++) {
        const src = r * g.a;
        const dst = (g.b - 1 - r) * g.a;
        for (let c = 0; c < g.a; c++) {
          img[dst + c] = this.cell(src + c);
        }
      }
      return img;
    }

    /** TM as a grey image of visit counts, the first row the grid's last. */
    countsImage() {
      const g = this.geo;
      const img = new Uint8Array(g.a * g.b);
      for (let r = 0; r < g.b; r++) {
        for (let c = 0; c < g.a; c++) {
          img[(g.b - 1 - r) * g.a + c] = countGrey(this.tm[r * g.a + c], g.tm_max);
        }
      }
      return img;
    }

    /**
     * The map files as the other tools write them (tools/telemetry.py send map --out):
     * om.pgm with its ROS map_server om.yaml (trinary), and tm.pgm. Null before a HELLO.
     */
    mapFiles() {
      if (this.geo === null) {
        return null;
      }
      const g = this.geo;
      const pgm = (img) => {
        const head = new TextEncoder().encode("P5\n" + g.a + " " + g.b + "\n255\n");
        const out = new Uint8Array(head.length + img.length);
        out.set(head, 0);
        out.set(img, head.length);
        return out;
      };
      const yaml = T.map.yaml.replace("%s", "om").replace("%s", umText(g.cell_um))
        .replace("%s", umText(g.origin_x_um)).replace("%s", umText(g.origin_y_um));
      return {"om.pgm": pgm(this.trinaryImage()), "om.yaml": yaml,
        "tm.pgm": pgm(this.countsImage())};
    }

    /** The map's figures: cells occupied, free and unknown. */
    cellCounts() {
      const c = {occupied: 0, free: 0, unknown: 0};
      if (this.geo === null) {
        return c;
      }
      for (let i = 0; i < this.om.length; i++) {
        const v = this.cell(i);
        if (v === T.map.occupied) {
          c.occupied++;
        } else if (v === T.map.free) {
          c.free++;
        } else {
          c.unknown++;
        }
      }
      return c;
    }
  }

  sv.model = {Model, umText, trinaryCell, countGrey, wrapRad, BAM_RAD};
})(window.slamview = window.slamview || {});
