// SPDX-License-Identifier: MIT
// Where the page's bytes come from and its commands go: the robot's UART through the Web
// Serial API, tools/telemetry.py serve over a WebSocket, or a recorded file played back.
// Each link only moves bytes: start(sink) hands every chunk to sink.bytes(Uint8Array), says
// sink.info(text) and sink.closed(why); send(Uint8Array) returns a promise. Decoding and
// drawing are elsewhere, so a test can feed the page without any of these.
"use strict";
(function (sv) {
  const P = sv.protocol;
  const BAUDS = [9600, 19200, 38400, 57600, 115200, 230400, 460800, 921600];

  /** The robot's UART through the Web Serial API (Chromium-based browsers). */
  class SerialLink {
    static available() {
      return typeof navigator !== "undefined" && "serial" in navigator;
    }

    constructor(baud) {
      this.baud = baud;
      this.port = null;
      this.reader = null;
      this.closing = false;
      this.name = "serial port at " + baud + " baud";
      this.canSend = true;
    }

    /** Asks the user for a port (the browser's chooser) and opens it. */
    async start(sink) {
      this.port = await navigator.serial.requestPort();
      await this.port.open({baudRate: this.baud, bufferSize: 65536});
      const info = this.port.getInfo ? this.port.getInfo() : {};
      if (info.usbVendorId !== undefined) {
        this.name = "USB serial " + info.usbVendorId.toString(16).padStart(4, "0") + ":" +
          info.usbProductId.toString(16).padStart(4, "0") + " at " + this.baud + " baud";
      }
      sink.info("connected to the " + this.name);
      this.loop(sink);
    }

    async loop(sink) {
      let why = "the port closed";
      try {
        while (this.port.readable && !this.closing) {
          this.reader = this.port.readable.getReader();
          try {
            for (;;) {
              const {value, done} = await this.reader.read();
              if (done) {
                break;
              }
              sink.bytes(value);
            }
          } catch (e) {
            // A framing or parity error ends one reader; the port goes on.
            if (this.closing) {
              break;
            }
            sink.info("serial: " + e.message);
          } finally {
            this.reader.releaseLock();
            this.reader = null;
          }
        }
      } catch (e) {
        why = e.message;
      }
      sink.closed(this.closing ? "disconnected" : why);
    }

    async send(bytes) {
      const w = this.port.writable.getWriter();
      try {
        await w.write(bytes);
      } finally {
        w.releaseLock();
      }
    }

    async close() {
      this.closing = true;
      if (this.reader) {
        await this.reader.cancel().catch(() => {});
      }
      if (this.port) {
        await this.port.close().catch(() => {});
      }
    }
  }

  /**
   * tools/telemetry.py serve: the robot's bytes as binary messages, the commands back the
   * same way; a text message is the bridge telling what it serves.
   */
  class SocketLink {
    constructor(url) {
      this.url = url;
      this.ws = null;
      this.name = url;
      this.canSend = true;
    }

    start(sink) {
      return new Promise((resolve, reject) => {
        let open = false;
        const ws = new WebSocket(this.url);
        this.ws = ws;
        ws.binaryType = "arraybuffer";
        ws.onopen = () => {
          open = true;
          sink.info("connected to " + this.url);
          resolve();
        };
        ws.onmessage = (ev) => {
          if (typeof ev.data === "string") {
            sink.info(ev.data);
          } else {
            sink.bytes(new Uint8Array(ev.data));
          }
        };
        ws.onclose = (ev) => {
          if (!open) {
            reject(new Error("cannot connect to " + this.url + " (is tools/telemetry.py serve " +
              "running there?)"));
          } else {
            sink.closed(ev.reason || "the bridge closed the connection");
          }
        };
      });
    }

    async send(bytes) {
      if (this.ws === null || this.ws.readyState !== WebSocket.OPEN) {
        throw new Error("not connected");
      }
      this.ws.send(bytes);
    }

    async close() {
      if (this.ws) {
        this.ws.close(1000, "closed by the page");
      }
    }
  }

  /**
   * A recorded telemetry file played at its own pace times a speed (1 to 100), or at once
   * to the end. The file is framed first to learn each frame's time (POSE, READING and
   * STATUS carry the tick count; the frames between them take the time before), then fed
   * in order up to the time the clock has reached; the bytes are the file's own, bad ones
   * included, so the page decodes a recording exactly as it would the robot.
   */
  class FileLink {
    constructor(bytes, name) {
      this.bytes = bytes;
      this.name = name;
      this.canSend = false;
      this.sent = 0;          // bytes fed so far
      this.speed = 1;
      this.playing = false;
      this.timer = null;
      this.finished = false;
      this.index();
    }

    index() {
      const dec = new P.Decoder();
      const ends = [];
      const ticks = [];
      let t = null;
      const CHUNK = 1 << 20;
      for (let i = 0; i < this.bytes.length; i += CHUNK) {
        for (const f of dec.feed(this.bytes.subarray(i, i + CHUNK))) {
          const timed = (f.type === P.POSE || f.type === P.READING || f.type === P.STATUS) &&
            f.payload.length >= 4;
          if (timed) {
            const k = new DataView(f.payload.buffer, f.payload.byteOffset, 4).getUint32(0, true);
            // A recording may span a reboot (the count starts again) or a long pause: the
            // playback clock never goes back and skips gaps longer than ten seconds.
            t = t === null ? k : k < t ? t : k - t > 1000 ? t + 10 : k;
          }
          ends.push(f.end);
          ticks.push(t);
        }
      }
      const first = ticks.find((k) => k !== null);
      this.t0 = first === undefined ? 0 : first;
      this.ends = ends;
      this.ticks = ticks.map((k) => (k === null ? this.t0 : k));
      this.t1 = this.ticks.length ? this.ticks[this.ticks.length - 1] : this.t0;
      this.next = 0;          // the next frame to feed
      this.clock = this.t0;   // the playback time, ticks
    }

    /** Seconds of the recording, and how far playback has come. */
    get duration() {
      return (this.t1 - this.t0) * 0.01;
    }

    get position() {
      return (this.clock - this.t0) * 0.01;
    }

    get done() {
      return this.sent >= this.bytes.length;
    }

    start(sink) {
      this.sink = sink;
      sink.info("opened " + this.name + ": " + this.bytes.length + " bytes, " +
        this.duration.toFixed(1) + " s");
      return Promise.resolve();
    }

    feedTo(offset) {
      if (offset > this.sent) {
        const chunk = this.bytes.subarray(this.sent, offset);
        this.sent = offset;
        this.sink.bytes(chunk);
      }
    }

    step(dtS) {
      this.clock += dtS * this.speed * 100;
      let k = this.next;
      while (k < this.ends.length && this.ticks[k] <= this.clock) {
        k++;
      }
      this.next = k;
      if (k === this.ends.length) {
        this.toEnd();
      } else if (k > 0) {
        this.feedTo(this.ends[k - 1]);
      }
    }

    play() {
      if (this.playing || this.done) {
        return;
      }
      this.playing = true;
      let last = performance.now();
      this.timer = setInterval(() => {
        const now = performance.now();
        this.step((now - last) / 1000);
        last = now;
      }, 40);
    }

    pause() {
      this.playing = false;
      if (this.timer !== null) {
        clearInterval(this.timer);
        this.timer = null;
      }
    }

    /** Everything left at once, the bytes after the last frame too, as dump reads them. */
    toEnd() {
      if (this.finished) {
        return;
      }
      this.finished = true;
      this.pause();
      this.next = this.ends.length;
      this.clock = this.t1;
      if (!this.done) {
        this.feedTo(this.bytes.length);
      }
      this.sink.closed("the end of " + this.name);
    }

    async send() {
      throw new Error("a recording takes no commands");
    }

    async close() {
      this.pause();
    }
  }

  sv.link = {SerialLink, SocketLink, FileLink, BAUDS};
})(window.slamview = window.slamview || {});
