// SPDX-License-Identifier: MIT
// The robot's telemetry link in the browser: frames, CRC, the decoder and the commands, as
// firmware/include/slam/telemetry.h specifies them and tools/slamtools/link.py implements them.
// Bytes in, plain objects out: no transport and no drawing here, so a test can feed it.
"use strict";
(function (sv) {
  const T = sv.tables;
  const SYNC0 = 0xa5;
  const SYNC1 = 0x5a;
  const HELLO = 1, POSE = 2, READING = 3, MAP_ROW = 4, STATUS = 5, ACK = 6, ERROR = 7,
    CONFIG = 8;
  const FRAME_NAMES = {1: "hello", 2: "pose", 3: "reading", 4: "map_row", 5: "status",
    6: "ack", 7: "error", 8: "config"};
  const STATUS_NAMES = ["ticks", "pings", "echoes", "timeouts", "om_hits", "overruns",
    "saves", "drops", "commands", "refused"];

  const CRC_TABLE = (function () {
    const t = new Uint16Array(256);
    for (let i = 0; i < 256; i++) {
      let crc = i << 8;
      for (let k = 0; k < 8; k++) {
        crc = crc & 0x8000 ? ((crc << 1) ^ 0x1021) & 0xffff : (crc << 1) & 0xffff;
      }
      t[i] = crc;
    }
    return t;
  })();

  /** CRC-16/CCITT-FALSE of bytes[from, to), as the firmware computes it. */
  function crc16(bytes, from, to) {
    let crc = 0xffff;
    for (let i = from; i < to; i++) {
      crc = ((crc << 8) & 0xffff) ^ CRC_TABLE[((crc >> 8) ^ bytes[i]) & 0xff];
    }
    return crc;
  }

  /** One frame: sync, type, length, payload, CRC (low byte first). */
  function frame(type, payload) {
    const p = payload || new Uint8Array(0);
    const out = new Uint8Array(6 + p.length);
    out[0] = SYNC0;
    out[1] = SYNC1;
    out[2] = type;
    out[3] = p.length;
    out.set(p, 4);
    const crc = crc16(out, 2, 4 + p.length);
    out[4 + p.length] = crc & 0xff;
    out[5 + p.length] = crc >> 8;
    return out;
  }

  /**
   * Bytes in, frames out, exactly as slamlink.Decoder: resynchronise on A5 5A, drop a
   * frame whose CRC fails (counted in `bad`, and one byte skipped past its sync), count
   * the bytes outside any frame in `skipped`. The buffer grows by doubling and is read
   * from an offset, so a long recording costs linear time.
   */
  class Decoder {
    constructor() {
      this.buf = new Uint8Array(1024);
      this.start = 0;   // first byte not yet consumed
      this.end = 0;     // one past the last byte held
      this.bad = 0;
      this.skipped = 0;
      this.consumed = 0; // bytes consumed since the first, frames and skipped alike
    }

    /** Bytes held: the start of a frame not complete yet. */
    get pending() {
      return this.end - this.start;
    }

    append(data) {
      const held = this.end - this.start;
      if (this.end + data.length > this.buf.length) {
        if (held + data.length <= this.buf.length >> 1) {
          this.buf.copyWithin(0, this.start, this.end);
        } else {
          let size = this.buf.length;
          while (size < (held + data.length) * 2) {
            size *= 2;
          }
          const nb = new Uint8Array(size);
          nb.set(this.buf.subarray(this.start, this.end));
          this.buf = nb;
        }
        this.start = 0;
        this.end = held;
      }
      this.buf.set(data, this.end);
      this.end += data.length;
    }

    drop(n) {
      this.start += n;
      this.consumed += n;
    }

    /** Feed bytes (a Uint8Array); returns [{type, payload, end}], end the stream offset
     *  one past the frame's last byte. */
    feed(data) {
      this.append(data);
      const b = this.buf;
      const out = [];
      for (;;) {
        let i = this.start;
        while (i + 1 < this.end && !(b[i] === SYNC0 && b[i + 1] === SYNC1)) {
          i++;
        }
        if (i + 1 >= this.end) {
          // No sync: keep a last A5, which may be the first half of one.
          const keep = this.end > this.start && b[this.end - 1] === SYNC0 ? 1 : 0;
          this.skipped += this.end - keep - this.start;
          this.drop(this.end - keep - this.start);
          break;
        }
        this.skipped += i - this.start;
        this.drop(i - this.start);
        const held = this.end - this.start;
        if (held < 6) {
          break;
        }
        const n = b[this.start + 3];
        if (held < 6 + n) {
          break;
        }
        const s = this.start;
        const crc = b[s + 4 + n] | (b[s + 5 + n] << 8);
        if (crc !== crc16(b, s + 2, s + 4 + n)) {
          this.bad++;
          this.skipped++;
          this.drop(1);
          continue;
        }
        out.push({type: b[s + 2], payload: b.slice(s + 4, s + 4 + n), end: this.consumed + 6 + n});
        this.drop(6 + n);
      }
      if (this.start === this.end) {
        this.start = this.end = 0;
      }
      return out;
    }
  }

  /**
   * A frame as an object, the same keys and values as slamlink.decode(); null when its
   * length is not its type's, or a field the page would trust holds what no robot sends (a
   * malformed frame, counted as bad): a HELLO's grid is T.map.sideMin..sideMax cells a side,
   * a map row lies within such a grid.
   */
  function decode(type, p) {
    const n = p.length;
    const v = new DataView(p.buffer, p.byteOffset, p.byteLength);
    const u32 = (o) => v.getUint32(o, true);
    const i32 = (o) => v.getInt32(o, true);
    const u16 = (o) => v.getUint16(o, true);
    const side = (c) => c >= T.map.sideMin && c <= T.map.sideMax;
    if (type === HELLO && (n === 19 || n === 39 || n === 42)) {
      if (!side(u16(1)) || !side(u16(3))) {
        return null;
      }
      const d = {type: "hello", version: p[0], a: u16(1), b: u16(3), cell_um: u32(5),
        origin_x_um: i32(9), origin_y_um: i32(13), om_max: p[17], tm_max: p[18],
        om_mode: T.map.omCount};
      if (n >= 39) {
        Object.assign(d, {confidence_radius_um: u32(19), range_min_um: u32(23),
          mount_x_um: i32(27), mount_y_um: i32(31), mount_yaw_mdeg: i32(35)});
      }
      if (n === 42) {
        Object.assign(d, {om_mode: p[39], om_hit: p[40], om_miss: p[41]});
      }
      return d;
    }
    if (type === POSE && n === 16) {
      return {type: "pose", ticks: u32(0), x_um: i32(4), y_um: i32(8), heading: u32(12)};
    }
    if (type === READING && n === 26) {
      return {type: "reading", ticks: u32(0), stop: p[4], outcome: p[5], servo_mdeg: i32(6),
        range_um: u32(10), x_um: i32(14), y_um: i32(18), heading: u32(22)};
    }
    if (type === MAP_ROW && n >= 5) {
      if (u16(1) >= T.map.sideMax || u16(3) + n - 5 > T.map.sideMax) {
        return null;
      }
      return {type: "map_row", map: p[0], row: u16(1), first: u16(3), cells: p.subarray(5)};
    }
    if (type === STATUS && (n === 32 || n === 42 || n === 46)) {
      const d = {};
      for (let k = 0; k < Math.min(n >> 2, 10); k++) {
        d[STATUS_NAMES[k]] = u32(4 * k);
      }
      d.type = "status";
      if (n >= 42) {
        d.explore_mode = p[40];
        d.flags = p[41];
      }
      // Points outside the grid (the home does not fit), sent once there are any.
      d.outside = n === 46 ? u32(42) : 0;
      return d;
    }
    if (type === ACK && n === 1) {
      return {type: "ack", command: p[0]};
    }
    if (type === ERROR && n === 3) {
      return {type: "error", command: p[0], code: p[1], key: p[2]};
    }
    if (type === CONFIG && n === 5) {
      return {type: "config", key: p[0], raw: v.getUint32(1, true)};
    }
    if (FRAME_NAMES[type] !== undefined) {
      return null;
    }
    return {type: "unknown", code: type, length: n};
  }

  /**
   * Bytes to decoded frames with the counts telemetry.py keeps: `bad` (a bad CRC or a
   * length that is not the type's), `skipped` bytes, `frames` taken.
   */
  class Stream {
    constructor(onFrame) {
      this.dec = new Decoder();
      this.onFrame = onFrame;
      this.frames = 0;
      this.malformed = 0;
    }

    get bad() {
      return this.dec.bad + this.malformed;
    }

    feed(bytes) {
      for (const f of this.dec.feed(bytes)) {
        const fr = decode(f.type, f.payload);
        if (fr === null) {
          this.malformed++;
          continue;
        }
        this.frames++;
        this.onFrame(fr, f.end);
      }
    }
  }

  // ---- the configuration keys and the commands --------------------------------------------

  const FIELD_BY_NAME = {};
  const FIELD_BY_ID = {};
  for (const f of T.fields) {
    FIELD_BY_NAME[f.name] = f;
    FIELD_BY_ID[f.id] = f;
  }
  const COMMAND_NAMES = {};
  for (const name of Object.keys(T.commands)) {
    COMMAND_NAMES[T.commands[name].type] = name;
  }

  class CommandError extends Error {}

  /** The value a CONFIG frame carries, as text (cal_* as decimals, a mode by name). */
  function keyValue(key, raw) {
    const f = FIELD_BY_ID[key];
    if (f === undefined) {
      return {name: "key" + key, text: String(raw)};
    }
    const v = f.wire === "I32" && raw >= 2 ** 31 ? raw - 2 ** 32 : raw;
    if (f.type === "Q30") {
      return {name: f.name, text: (v / 2 ** 30).toFixed(9)};
    }
    if (f.name === "explore_mode" && v < T.modes.length) {
      return {name: f.name, text: v + " (" + T.modes[v].name + ")"};
    }
    return {name: f.name, text: String(v)};
  }

  /**
   * The frame of a command: command("stop"), command("mode", "walls"),
   * command("get", "cruise_mm_s"), command("set", "cruise_mm_s", "150"). A value must fit
   * its field's type; a field SET may change while the robot runs must also lie in its
   * range (the robot checks the rest). Throws CommandError with the reason in words.
   */
  function command(name, arg, value) {
    const c = T.commands[name];
    if (c === undefined) {
      throw new CommandError("no such command: " + name);
    }
    if (name === "mode") {
      const m = T.modes.findIndex((x) => x.name === arg);
      if (m < 0) {
        throw new CommandError("mode: '" + arg + "' is not one of " +
          T.modes.map((x) => x.name).join(", "));
      }
      return frame(c.type, Uint8Array.of(m));
    }
    if (name === "get" || name === "set") {
      const f = FIELD_BY_NAME[arg];
      if (f === undefined) {
        throw new CommandError("unknown key '" + arg + "'");
      }
      if (name === "get") {
        return frame(c.type, Uint8Array.of(f.id));
      }
      const text = String(value).trim();
      let v;
      if (f.type === "Q30") {
        if (!/^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$/.test(text)) {
          throw new CommandError("set " + f.name + ": '" + text + "' is not a decimal factor");
        }
        v = Math.round(Number(text) * 2 ** 30);
      } else {
        if (!/^[-+]?\d+$/.test(text)) {
          throw new CommandError("set " + f.name + ": '" + text + "' is not a whole number");
        }
        v = Number(text);
      }
      const [lo, hi] = T.typeRange[f.wire];
      if (!(v >= lo && v <= hi)) {
        throw new CommandError("set " + f.name + ": " + text + " does not fit its field (" +
          lo + " .. " + hi + ")");
      }
      if (f.live && !(v >= f.lo && v <= f.hi)) {
        throw new CommandError("set " + f.name + ": " + text + " is out of its range, " +
          f.words);
      }
      const p = new Uint8Array(5);
      p[0] = f.id;
      new DataView(p.buffer).setUint32(1, v >>> 0, true);
      return frame(c.type, p);
    }
    return frame(c.type);
  }

  /** An answer (ACK, ERROR, CONFIG) in words; null for any other frame. */
  function answerText(fr) {
    if (fr.type === "ack") {
      return (COMMAND_NAMES[fr.command] || "command 0x" + fr.command.toString(16)) +
        ": done";
    }
    if (fr.type === "error") {
      const what = T.errors[fr.code];
      const name = COMMAND_NAMES[fr.command] || "command 0x" + fr.command.toString(16);
      const key = fr.key ? " " + (FIELD_BY_ID[fr.key] ? FIELD_BY_ID[fr.key].name : "key " + fr.key)
        : "";
      return name + key + " refused: " + (what ? T.errorText[what] : "code " + fr.code);
    }
    if (fr.type === "config") {
      const kv = keyValue(fr.key, fr.raw);
      return kv.name + " = " + kv.text;
    }
    return null;
  }

  sv.protocol = {HELLO, POSE, READING, MAP_ROW, STATUS, ACK, ERROR, CONFIG, FRAME_NAMES,
    crc16, frame, Decoder, decode, Stream, command, CommandError, keyValue, answerText,
    FIELD_BY_NAME, FIELD_BY_ID, COMMAND_NAMES};
})(window.slamview = window.slamview || {});
