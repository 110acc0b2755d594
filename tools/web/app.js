// SPDX-License-Identifier: MIT
// The page: wires a link (link.js) to the decoder (protocol.js), the model (model.js) and
// the drawing (view.js), and the controls to the commands. window.slamview.app is its
// handle for tests and the console: feed(bytes), open(bytes, name), connectSocket(url),
// command(name, arg, value), mapFiles(); window.slamview.state is the model.
"use strict";
(function (sv) {
  const T = sv.tables;
  const P = sv.protocol;
  const $ = (id) => document.getElementById(id);
  const SPEEDS = [1, 2, 5, 10, 20, 50, 100];

  const model = new sv.model.Model();
  const view = new sv.view.View(model, $("om"), $("tm"));
  let stream = new P.Stream((fr) => model.take(fr));
  let link = null;
  let sent = [];  // commands sent, oldest first: {name, text}

  function setState(text) {
    $("link-state").textContent = text;
  }

  /** Bytes from whatever link: decoded into the model. */
  function feed(bytes) {
    stream.feed(bytes);
    words.request();
  }

  // ---- the links -------------------------------------------------------------------------

  const sink = {
    bytes: feed,
    info: (text) => setState(text),
    closed: (why) => {
      if (link instanceof sv.link.FileLink) {
        setState("Played " + link.name + " to its end.");
      } else {
        setState("Disconnected: " + why + ".");
        link = null;
      }
      controls();
      words.request();
    },
  };

  async function attach(newLink) {
    await detach();
    clear();
    link = newLink;
    controls();
    try {
      await link.start(sink);
    } catch (e) {
      setState(e.message);
      link = null;
    }
    controls();
  }

  async function detach() {
    if (link !== null) {
      const old = link;
      link = null;
      await old.close();
    }
  }

  function clear() {
    stream = new P.Stream((fr) => model.take(fr));
    model.reset();
    sent = [];
    $("answers").textContent = "";
    words.request();
  }

  /** A recording (a Uint8Array) to play: paused at its start until play() or toEnd(). */
  async function open(bytes, name) {
    await attach(new sv.link.FileLink(bytes, name));
    link.speed = Number($("speed").value);
    controls();
  }

  function connectSocket(url) {
    return attach(new sv.link.SocketLink(url));
  }

  async function connectSerial() {
    if (!sv.link.SerialLink.available()) {
      setState("This browser has no Web Serial: use Chrome, Edge or Opera (from a file:// " +
        "page, http://localhost or https), or the WebSocket bridge.");
      return;
    }
    await attach(new sv.link.SerialLink(Number($("baud").value)));
  }

  function controls() {
    const file = link instanceof sv.link.FileLink ? link : null;
    $("play").disabled = file === null || file.done;
    $("play").textContent = file !== null && file.playing ? "Pause" : "Play";
    $("to-end").disabled = file === null || file.done;
    $("disconnect").disabled = link === null || file !== null;
    const live = link !== null && link.canSend;
    for (const b of document.querySelectorAll("#commands button")) {
      b.disabled = b.id === "download" ? model.geo === null : !live;
    }
  }

  // ---- commands --------------------------------------------------------------------------

  /** Send a command (protocol.command's words); its answer shows when it comes. */
  async function command(name, arg, value) {
    let bytes;
    try {
      bytes = P.command(name, arg, value);
    } catch (e) {
      answer(e.message, false);
      return false;
    }
    if (link === null || !link.canSend) {
      answer(name + ": no robot connected to send it to", false);
      return false;
    }
    try {
      await link.send(bytes);
    } catch (e) {
      answer(name + ": " + e.message, false);
      return false;
    }
    const text = [name, arg, value].filter((x) => x !== undefined && x !== "").join(" ");
    sent.push({name, text});
    answer("sent: " + text, null);
    return true;
  }

  function answer(text, ok) {
    const li = document.createElement("li");
    li.textContent = text;
    li.className = ok === null ? "sent" : ok ? "ok" : "refused";
    const list = $("answers");
    list.insertBefore(li, list.firstChild);
    while (list.childNodes.length > 200) {
      list.removeChild(list.lastChild);
    }
  }

  let answered = 0;
  model.listen((what) => {
    if (what === "reset") {
      answered = 0;
    }
    while (answered < model.answers.length) {
      const a = model.answers[answered++];
      answer(clock(a.ticks) + "  " + a.text, a.ok);
    }
  });

  // ---- the run in words --------------------------------------------------------------------

  function clock(ticks) {
    const s = ticks * T.tickS;
    const m = Math.floor(s / 60);
    return (m > 0 ? m + " min " : "") + (s - 60 * m).toFixed(1) + " s";
  }

  function num(n) {
    return n.toLocaleString("en-GB");
  }

  function figures() {
    const m = model;
    const st = m.status;
    const g = m.geo;
    const out = [];
    if (st === null && g === null) {
      return "No telemetry yet.";
    }
    out.push("At " + clock(m.ticks) + ":");
    if (st !== null) {
      const pct = st.pings ? " (" + Math.round(100 * st.echoes / st.pings) + " %)" : "";
      out.push(num(st.pings) + " pings, " + num(st.echoes) + " echoes" + pct + ", " +
        num(st.timeouts) + " timeouts; " + num(st.om_hits) + " hits put into OM.");
    }
    if (g !== null) {
      const c = m.cellCounts();
      const cell = g.cell_um * 1e-6;
      out.push("The map, " + g.a + " × " + g.b + " cells of " + Math.round(cell * 1000) +
        " mm, holds " + num(c.occupied) + " occupied cells and " + num(c.free) + " free (" +
        (c.free * cell * cell).toFixed(1) + " m² seen free); " + num(c.unknown) +
        " are unknown.");
    }
    if (m.pose !== null) {
      const th = sv.model.wrapRad(m.pose.heading) * 180 / Math.PI;
      out.push("The robot has driven " + m.pathM.toFixed(1) + " m and stands at x " +
        (m.pose.x_um * 1e-6).toFixed(2) + " m, y " + (m.pose.y_um * 1e-6).toFixed(2) +
        " m, heading " + th.toFixed(1) + "°.");
    }
    if (st !== null) {
      out.push((st.overruns ? num(st.overruns) + " ticks overran their period" :
        "No tick overran its period") + "; " + num(st.drops) + " telemetry events dropped; " +
        num(st.saves) + " map saves; " + num(st.commands) + " commands taken, " +
        num(st.refused) + " refused.");
    }
    return out.join(" ");
  }

  function robotState() {
    const st = model.status;
    if (st === null) {
      return "";
    }
    const parts = [];
    if (st.explore_mode !== undefined) {
      const mode = T.modes[st.explore_mode];
      parts.push("Mode: " + (mode ? mode.name + " (" + mode.summary + ")" : st.explore_mode) + ".");
      parts.push(st.flags & T.flags.stopped ? "Stopped: STOP is in force (the sweep goes on " +
        "mapping); Start drives again." : "Driving.");
      if (st.flags & T.flags.pending) {
        parts.push("A command waits for the robot to stand.");
      }
      if (st.flags & T.flags.explored) {
        parts.push("Explored: no frontier it can reach is left; it stands.");
      }
    }
    return parts.join(" ");
  }

  function linkCounts() {
    const d = stream.dec;
    const parts = [num(stream.frames) + " frames"];
    parts.push(num(stream.bad) + " bad frames skipped (bad CRC or length)");
    if (d.skipped) {
      parts.push(num(d.skipped) + " bytes outside frames");
    }
    if (model.badRows) {
      parts.push(num(model.badRows) + " map rows outside the grid skipped");
    }
    if (link instanceof sv.link.FileLink && link.done && d.pending >= 2) {
      parts.push("the last " + d.pending + " bytes are a frame cut short");
    }
    return parts.join("; ") + ".";
  }

  // The words change with every frame; they are written at most four times a second.
  const words = {
    due: false,
    request() {
      if (!this.due) {
        this.due = true;
        setTimeout(() => {
          this.due = false;
          $("figures").textContent = figures();
          $("robot-state").textContent = robotState();
          $("link-counts").textContent = linkCounts();
          if (link instanceof sv.link.FileLink) {
            $("progress").max = Math.max(link.duration, 0.01);
            $("progress").value = link.position;
            $("clock").textContent = link.position.toFixed(1) + " / " +
              link.duration.toFixed(1) + " s";
          }
          controls();
        }, 250);
      }
    },
  };

  // ---- the map files -----------------------------------------------------------------------

  function mapFiles() {
    return model.mapFiles();
  }

  function download() {
    const files = mapFiles();
    if (files === null) {
      return;
    }
    for (const [name, data] of Object.entries(files)) {
      const a = document.createElement("a");
      a.href = URL.createObjectURL(new Blob([data], {type: "application/octet-stream"}));
      a.download = name;
      document.body.appendChild(a);
      a.click();
      setTimeout(() => {
        URL.revokeObjectURL(a.href);
        a.remove();
      }, 1000);
    }
  }

  // ---- the controls ------------------------------------------------------------------------

  function setup() {
    for (const b of sv.link.BAUDS) {
      $("baud").add(new Option(b + " baud", b, b === 115200, b === 115200));
    }
    if (!sv.link.SerialLink.available()) {
      $("serial-note").textContent = "(this browser has no Web Serial)";
    }
    for (const s of SPEEDS) {
      $("speed").add(new Option(s + "×", s, s === 10, s === 10));
    }
    for (const m of T.modes) {
      $("mode").add(new Option(m.name + " — " + m.summary, m.name, false, m.name === "walls"));
    }
    for (const f of T.fields) {
      $("key").add(new Option(f.name, f.name));
    }
    const keyNote = () => {
      const f = P.FIELD_BY_NAME[$("key").value];
      const known = model.config[f.name];
      $("key-note").textContent = f.words + (f.type === "Q30" ? ", a decimal factor" : "") +
        (f.live ? "" : "; takes effect only when the robot starts") +
        (known !== undefined ? "; the robot said " + known : "");
    };
    $("key").addEventListener("change", keyNote);
    model.listen((what, fr) => {
      if (what === "frame" && fr.type === "config") {
        keyNote();
      }
    });
    keyNote();
    if (location.protocol === "http:" || location.protocol === "https:") {
      $("ws-url").value = (location.protocol === "https:" ? "wss://" : "ws://") + location.host +
        "/link";
    }

    $("serial-connect").onclick = connectSerial;
    $("ws-connect").onclick = () => connectSocket($("ws-url").value.trim());
    $("file").onchange = async (ev) => {
      const f = ev.target.files[0];
      if (f) {
        await open(new Uint8Array(await f.arrayBuffer()), f.name);
        link.play();
        controls();
      }
    };
    $("speed").onchange = () => {
      if (link instanceof sv.link.FileLink) {
        link.speed = Number($("speed").value);
      }
    };
    $("play").onclick = () => {
      if (link instanceof sv.link.FileLink) {
        if (link.playing) {
          link.pause();
        } else {
          link.play();
        }
        controls();
      }
    };
    $("to-end").onclick = () => {
      if (link instanceof sv.link.FileLink) {
        link.toEnd();
      }
    };
    $("disconnect").onclick = async () => {
      await detach();
      setState("Disconnected.");
      controls();
    };
    $("clear").onclick = clear;
    for (const b of document.querySelectorAll("#commands button[data-cmd]")) {
      b.onclick = () => command(b.dataset.cmd);
    }
    $("mode-send").onclick = () => command("mode", $("mode").value);
    $("get").onclick = () => command("get", $("key").value);
    $("set").onclick = () => command("set", $("key").value, $("value").value);
    $("download").onclick = download;
    window.addEventListener("resize", () => view.request());
    controls();
    words.request();
    view.request();

    // Served by the bridge (tools/telemetry.py serve), the page connects to it at once.
    if (new URLSearchParams(location.search).has("connect")) {
      connectSocket($("ws-url").value);
    }
  }

  sv.app = {
    feed, open, connectSocket, connectSerial, command, mapFiles, clear, model, view,
    get stream() {
      return stream;
    },
    get link() {
      return link;
    },
    get sent() {
      return sent;
    },
  };
  sv.state = model;
  setup();
})(window.slamview = window.slamview || {});
