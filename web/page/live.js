// The live page: draws what the engine (astrojax.js, the project's C++ compiled to WebAssembly)
// computes, and turns the controls into its calls. No physics here: positions, modes, energies
// and the orbit class all come from the engine.
// A classic script, not an ES module: browsers refuse module scripts from file://, and the
// page must open from a copy of the site.
'use strict';
(function () {
  const PI = Math.PI;
  const OMEGA_MAX = 20;  // the ω_m slider's end [π rad/s]
  // The sliders: the --set key of sweeps/live.toml, what the page shows, display = value·scale.
  const SLIDERS = [
    {key: 'model.drive_radius', label: 'R', unit: 'mm', scale: 1e3, min: 1, max: 30},
    {key: 'model.string_length', label: 'l', unit: 'm', scale: 1, min: 0.3, max: 1.5},
    {key: 'model.bead_mass', label: 'm1', unit: 'g', scale: 1e3, min: 1, max: 200},
    {key: 'model.ball_mass', label: 'm2', unit: 'g', scale: 1e3, min: 1, max: 200},
    {key: 'model.contact_distance', label: 'd', unit: 'cm', scale: 1e2, min: 1, max: 10},
    {key: 'model.mu_static', label: 'μ_s', unit: '', scale: 1, min: 0, max: 1},
    {key: 'model.mu_kinetic', label: 'μ_k', unit: '', scale: 1, min: 0, max: 1},
    {key: 'model.drag', label: 'c_D', unit: 'g/s', scale: 1e3, min: 0, max: 10},
  ];
  const PARAM_OF = {  // engine.parameters() field of each slider
    'model.drive_radius': 'R', 'model.string_length': 'l', 'model.bead_mass': 'm1', 'model.ball_mass': 'm2',
    'model.contact_distance': 'd', 'model.mu_static': 'muS', 'model.mu_kinetic': 'muK', 'model.drag': 'cD',
  };
  // physics::Mode
  const MODES = [
    {name: 'sliding', color: '#e08a00'}, {name: 'on the bottom ball', color: '#1f6fd1'},
    {name: 'stuck (held by friction)', color: '#1a9a45'}, {name: 'at the top stop', color: '#8a3fc7'},
    {name: 'string slack', color: '#d62728'},
  ];
  const CLASS_COLOR = {
    'fallen': '#808080', 'locked-circular': '#1a9a45', 'lagging-circular': '#1f6fd1', 'flower': '#d62728',
    'not-settled': '#e0a000', 'failed': '#000000',
  };
  const TRAIL_SECONDS = 1.5;
  const CLASSIFY_EVERY = 0.25;  // [s] of simulated time

  const $ = (id) => document.getElementById(id);
  const live = {ready: false, errors: [], trace: [], verdict: null, realtime: null, consoleErrors: []};
  window.astrojaxLive = live;  // read by the browser tests (tests/web/)

  let engine = null;
  let overrides = {};           // --set key -> value text, as in the page's address
  let startKind = 'locked';     // 'rest', 'table1' or 'locked'
  const SEEDS = {rest: 'hanging', table1: 'circular_high', locked: 'locked_orbit'};  // sweep/seeds.hpp
  let startOmega = 4.5 * PI;
  let trail = [];               // {t, r1, r2, mode}
  let nextClassify = 0;
  let crossings = [];           // times the bottom ball crossed the +x half-plane upwards [s]
  let lastSample = null;
  let failed = false;

  function showError(text) {
    const box = $('error');
    box.textContent = text ? 'error: ' + text : '';
    box.hidden = !text;
    if (text) live.errors.push(text);
  }

  // ---- the set-up in the address -----------------------------------------------------------
  function readAddress() {
    const q = new URLSearchParams(window.location.search);
    const problems = [];
    for (const [k, v] of q) {
      if (k.startsWith('model.') || k.startsWith('layers.')) overrides[k] = v;
      else if (k === 'start') {
        if (v in SEEDS) startKind = v;
        else problems.push(`address key 'start': '${v}' is not allowed; allowed: rest, table1, locked`);
      } else if (k === 'omega') {
        const w = Number(v);
        if (v !== '' && Number.isFinite(w) && w >= 0 && w <= OMEGA_MAX * PI) startOmega = w;
        else problems.push(`address key 'omega': ${v} is out of range; allowed [0, ${(OMEGA_MAX * PI).toFixed(4)}] rad/s`);
      } else if (k === 'rate') {
        const r = Number(v);
        if (Number.isFinite(r) && r > 0 && r <= 50) $('rate').value = String(r);
        else problems.push(`address key 'rate': ${v} is out of range; allowed (0, 50] rad/s^2`);
      } else problems.push(`address key '${k}': unknown; allowed: start, omega, rate, model.KEY, layers.KEY`);
    }
    if (!q.has('omega') && startKind === 'rest') startOmega = 0;
    return problems;
  }

  function writeAddress() {
    const q = new URLSearchParams();
    q.set('start', startKind);
    q.set('omega', String(+engine.omegaTarget().toPrecision(12)));
    q.set('rate', $('rate').value);
    for (const k of Object.keys(overrides).sort()) q.set(k, overrides[k]);
    history.replaceState(null, '', '?' + q.toString());
  }

  // Every override at once, as the command line's --set would apply them. On a refusal the
  // engine keeps its model; the refused key is dropped and the controls show the model again.
  function configure(changedKey) {
    const list = Object.keys(overrides).map((k) => `${k}=${overrides[k]}`);
    const err = engine.configure(list);
    if (err) {
      showError(err);
      if (changedKey) delete overrides[changedKey];
    } else {
      showError('');
      resetLedgerViews();
    }
    syncControls();
    writeAddress();
    return !err;
  }

  // ---- controls ------------------------------------------------------------------------------
  function format(x) {
    return Number.isFinite(x) ? String(+x.toPrecision(4)) : '–';
  }

  function buildSliders() {
    const box = $('sliders');
    const omega = document.createElement('label');
    omega.className = 'slider';
    omega.innerHTML = '<span class="name">ω_m</span><input id="omega-slider" type="range" min="0" ' +
        `max="${OMEGA_MAX}" step="0.05"><span class="value" id="omega-value"></span>`;
    box.appendChild(omega);
    for (const s of SLIDERS) {
      const el = document.createElement('label');
      el.className = 'slider';
      el.innerHTML = `<span class="name">${s.label}</span><input type="range" min="${s.min}" max="${s.max}" ` +
          `step="any" data-key="${s.key}"><span class="value"></span>`;
      box.appendChild(el);
      const input = el.querySelector('input');
      input.addEventListener('input', () => {
        el.querySelector('.value').textContent = `${format(+input.value)} ${s.unit}`;
      });
      input.addEventListener('change', () => {
        overrides[s.key] = String(+(input.value / s.scale).toPrecision(6));
        configure(s.key);
      });
    }
    const os = $('omega-slider');
    os.addEventListener('input', () => {
      $('omega-value').textContent = `${(+os.value).toFixed(2)}π rad/s`;
    });
    os.addEventListener('change', () => rampTo(+os.value * PI));
  }

  function syncControls() {
    const p = engine.parameters();
    for (const input of document.querySelectorAll('#sliders input[data-key]')) {
      const s = SLIDERS.find((x) => x.key === input.dataset.key);
      const v = p[PARAM_OF[s.key]] * s.scale;
      input.value = String(v);
      input.parentElement.querySelector('.value').textContent = `${format(v)} ${s.unit}`;
    }
    $('friction').value = p.friction;
    $('friction_law').value = p.frictionLaw;
    $('clutch').checked = p.clutch;
    const target = engine.omegaTarget() / PI;
    $('omega-slider').value = String(target);
    $('omega-value').textContent = `${target.toFixed(2)}π rad/s`;
  }

  function rate() {
    const r = +$('rate').value;
    return Number.isFinite(r) && r > 0 ? r : 1;
  }

  function rampTo(omega) {
    const err = engine.ramp(omega, rate());
    if (err) showError(err);
    syncControls();
    writeAddress();
  }

  function start(kind) {
    startKind = kind;
    const err = engine.start(SEEDS[kind], startOmega);
    failed = !!err;
    if (err) showError(err);
    live.trace = [];
    resetLedgerViews();
    syncControls();
    writeAddress();
  }

  function resetLedgerViews() {
    trail = [];
    crossings = [];
    lastSample = null;
    nextClassify = engine.time() + CLASSIFY_EVERY;
  }

  function wireControls() {
    $('start-rest').addEventListener('click', () => { startOmega = 0; start('rest'); });
    const atOmega = (kind) => () => {  // at the slider's ω_m (4.5π when it is at rest)
      startOmega = +$('omega-slider').value * PI || 4.5 * PI;
      start(kind);
    };
    $('start-table1').addEventListener('click', atOmega('table1'));
    $('start-locked').addEventListener('click', atOmega('locked'));
    $('hold').addEventListener('click', () => { engine.hold(); syncControls(); writeAddress(); });
    $('ramp-up').addEventListener('click', () => rampTo(OMEGA_MAX * PI));
    $('ramp-down').addEventListener('click', () => rampTo(0));
    $('rate').addEventListener('change', writeAddress);
    const layer = (key, value) => { overrides[key] = value; configure(key); };
    $('friction').addEventListener('change', (e) => layer('layers.friction', e.target.value));
    $('friction_law').addEventListener('change', (e) => layer('layers.friction_law', e.target.value));
    $('clutch').addEventListener('change', (e) => layer('layers.tie', e.target.checked ? 'clutch' : 'rigid'));
    $('legend').innerHTML = 'bead: ' + MODES.map((m) =>
        `<span><i style="background:${m.color}"></i>${m.name}</span>`).join(' ');
  }

  // ---- drawing -------------------------------------------------------------------------------
  function viewScale(canvas) {
    const l = engine.parameters().l;
    return (canvas.height - 30) / (1.08 * l);
  }

  function drawTrail(ctx, proj, now) {
    for (const ball of ['r1', 'r2']) {
      for (let i = 1; i < trail.length; ++i) {
        const age = now - trail[i].t;
        ctx.strokeStyle = ball === 'r1' ? `rgba(224,138,0,${1 - age / TRAIL_SECONDS})`
                                        : `rgba(60,60,60,${1 - age / TRAIL_SECONDS})`;
        ctx.lineWidth = 1.5;
        ctx.beginPath();
        ctx.moveTo(...proj(trail[i - 1][ball]));
        ctx.lineTo(...proj(trail[i][ball]));
        ctx.stroke();
      }
    }
  }

  function drawBalls(ctx, proj, pos, mode) {
    const a = proj([pos[0], pos[1], pos[2]]), b = proj([pos[3], pos[4], pos[5]]), c = proj([pos[6], pos[7], pos[8]]);
    ctx.strokeStyle = mode === 4 ? '#d62728' : '#333';
    ctx.setLineDash(mode === 4 ? [5, 4] : []);
    ctx.lineWidth = 1.2;
    ctx.beginPath();
    ctx.moveTo(...a); ctx.lineTo(...b); ctx.lineTo(...c);
    ctx.stroke();
    ctx.setLineDash([]);
    ctx.fillStyle = '#444';
    ctx.beginPath(); ctx.arc(...c, 8, 0, 2 * PI); ctx.fill();
    ctx.fillStyle = MODES[mode].color;
    ctx.beginPath(); ctx.arc(...b, 7, 0, 2 * PI); ctx.fill();
    ctx.strokeStyle = '#222'; ctx.lineWidth = 1; ctx.stroke();
  }

  function drawFront(pos, mode, now) {
    const cv = $('front'), ctx = cv.getContext('2d');
    const k = viewScale(cv), ox = cv.width / 2, oy = 15;
    const proj = (r) => [ox + k * r[0], oy - k * r[2]];
    ctx.clearRect(0, 0, cv.width, cv.height);
    ctx.fillStyle = '#888';
    ctx.fillRect(ox - 2, 0, 4, oy);  // the motor's axis
    ctx.strokeStyle = '#888'; ctx.lineWidth = 3;
    ctx.beginPath(); ctx.moveTo(ox, oy); ctx.lineTo(...proj(pos)); ctx.stroke();  // the rod
    drawTrail(ctx, proj, now);
    drawBalls(ctx, proj, pos, mode);
    scaleBar(ctx, k, cv.height);
  }

  function drawBottom(pos, mode, now) {
    const cv = $('bottom'), ctx = cv.getContext('2d');
    const k = viewScale(cv) * 1.4, ox = cv.width / 2, oy = cv.height / 2;
    // From below: x mirrored, so a turn the motor makes counter-clockwise from above shows clockwise.
    const proj = (r) => [ox - k * r[0], oy - k * r[1]];
    ctx.clearRect(0, 0, cv.width, cv.height);
    ctx.strokeStyle = '#ddd'; ctx.lineWidth = 1;
    for (const rho of [0.1, 0.2, 0.3]) { ctx.beginPath(); ctx.arc(ox, oy, k * rho, 0, 2 * PI); ctx.stroke(); }
    ctx.strokeStyle = '#888'; ctx.lineWidth = 3;
    ctx.beginPath(); ctx.moveTo(ox, oy); ctx.lineTo(...proj(pos)); ctx.stroke();
    drawTrail(ctx, proj, now);
    drawBalls(ctx, proj, pos, mode);
    ctx.fillStyle = '#666'; ctx.font = '11px sans-serif';
    ctx.fillText('circles: 10, 20, 30 cm from the axis', 8, cv.height - 8);
  }

  function scaleBar(ctx, k, h) {
    ctx.strokeStyle = '#666'; ctx.lineWidth = 2;
    ctx.beginPath(); ctx.moveTo(10, h - 12); ctx.lineTo(10 + 0.1 * k, h - 12); ctx.stroke();
    ctx.fillStyle = '#666'; ctx.font = '11px sans-serif';
    ctx.fillText('10 cm', 14 + 0.1 * k, h - 8);
  }

  function drawTrace() {
    const cv = $('trace'), ctx = cv.getContext('2d');
    const L = 42, B = cv.height - 34, W = cv.width - L - 12, H = B - 10;
    let top = 6;
    for (const p of live.trace) top = Math.max(top, Math.ceil(p.wm + 0.5), Math.ceil(p.wb + 0.5));
    top = Math.max(top, Math.ceil(engine.omegaM() / PI + 0.5));
    const X = (w) => L + W * w / top, Y = (w) => B - H * w / top;
    ctx.clearRect(0, 0, cv.width, cv.height);
    ctx.strokeStyle = '#ccc'; ctx.fillStyle = '#444'; ctx.font = '11px sans-serif'; ctx.lineWidth = 1;
    const tick = top > 12 ? 4 : 2;
    for (let w = 0; w <= top; w += tick) {
      ctx.beginPath(); ctx.moveTo(X(w), B); ctx.lineTo(X(w), Y(top)); ctx.stroke();
      ctx.beginPath(); ctx.moveTo(L, Y(w)); ctx.lineTo(X(top), Y(w)); ctx.stroke();
      ctx.fillText(`${w}`, X(w) - 4, B + 14);
      ctx.fillText(`${w}`, L - 18, Y(w) + 4);
    }
    ctx.fillText('ω_m / π [rad/s]', L + W / 2 - 40, B + 28);
    ctx.save(); ctx.translate(12, B - H / 2 + 30); ctx.rotate(-PI / 2); ctx.fillText('ω_ball / π', 0, 0); ctx.restore();
    ctx.setLineDash([4, 4]); ctx.strokeStyle = '#999';
    ctx.beginPath(); ctx.moveTo(X(0), Y(0)); ctx.lineTo(X(top), Y(top)); ctx.stroke();
    ctx.setLineDash([]);
    ctx.fillStyle = '#999'; ctx.fillText('ω_ball = ω_m (locked)', X(top * 0.55), Y(top * 0.55) - 8);
    for (let i = 0; i < live.trace.length; ++i) {
      const p = live.trace[i];
      ctx.fillStyle = CLASS_COLOR[p.cls] || '#000';
      ctx.beginPath(); ctx.arc(X(p.wm), Y(p.wb), 2.5, 0, 2 * PI); ctx.fill();
    }
    let x = L + 4;
    for (const c of ['fallen', 'locked-circular', 'lagging-circular', 'flower', 'not-settled']) {
      ctx.fillStyle = CLASS_COLOR[c];
      ctx.beginPath(); ctx.arc(x + 4, 12, 4, 0, 2 * PI); ctx.fill();
      ctx.fillStyle = '#333'; ctx.fillText(c, x + 11, 16);
      x += ctx.measureText(c).width + 22;
    }
  }

  function drawEnergy() {
    const cv = $('energy'), ctx = cv.getContext('2d');
    const e = engine.energies();  // E_k, E_p, W_m, drag, friction, impact, ΔE, residual [J]
    const rows = [
      ['motor work W_m', e[2], '#555'], ['ΔE = Δ(kinetic + potential)', e[6], '#1f6fd1'],
      ['air drag heat', e[3], '#e0a000'], ['friction heat (bead on string)', e[4], '#d62728'],
      ['impacts of the string', e[5], '#8a3fc7'],
    ];
    const M = Math.max(1e-6, ...rows.map((r) => Math.abs(r[1])));
    ctx.clearRect(0, 0, cv.width, cv.height);
    const L = 190, W = cv.width - L - 70, zero = L + W * 0.2;
    ctx.font = '12px sans-serif';
    rows.forEach(([name, v, color], i) => {
      const y = 14 + i * 34;
      ctx.fillStyle = '#333'; ctx.fillText(name, 6, y + 13);
      ctx.fillStyle = color;
      const w = 0.8 * W * v / M;
      ctx.fillRect(w >= 0 ? zero : zero + w, y, Math.abs(w), 18);
      ctx.fillStyle = '#333'; ctx.fillText(`${(1e3 * v).toFixed(1)} mJ`, L + W + 4, y + 13);
    });
    ctx.strokeStyle = '#999';
    ctx.beginPath(); ctx.moveTo(zero, 8); ctx.lineTo(zero, 14 + rows.length * 34 - 12); ctx.stroke();
    ctx.fillStyle = '#555';
    ctx.fillText(`now: kinetic ${(1e3 * e[0]).toFixed(1)} mJ; W_m − ΔE − heat = ${(1e6 * e[7]).toFixed(2)} µJ`,
                 6, cv.height - 8);
  }

  // ---- the period timer: the bottom ball crossing the +x half-plane, turning either way ------
  function timePeriods(samples) {
    for (let i = 0; i < samples.length; i += 9) {
      const s = {t: samples[i], r1: [samples[i + 2], samples[i + 3], samples[i + 4]],
                 r2: [samples[i + 5], samples[i + 6], samples[i + 7]], mode: samples[i + 8]};
      if (lastSample) {
        const [x0, y0] = lastSample.r2, [x1, y1] = s.r2;
        if (x0 > 0 && x1 > 0 && Math.hypot(x1, y1) > 5e-3 && (y0 < 0) !== (y1 < 0) && y1 !== y0) {
          crossings.push({t: lastSample.t + (s.t - lastSample.t) * (-y0 / (y1 - y0)), up: y1 > y0});
          if (crossings.length > 6) crossings.shift();
        }
      }
      lastSample = s;
      trail.push(s);
    }
    const now = trail.length ? trail[trail.length - 1].t : 0;
    while (trail.length && trail[0].t < now - TRAIL_SECONDS) trail.shift();
  }

  function periodText() {
    const n = crossings.length;
    if (n < 2 || crossings[n - 1].up !== crossings[n - 2].up) return 'the bottom ball has not yet gone round';
    const T = crossings[n - 1].t - crossings[n - 2].t;
    if (engine.time() - crossings[n - 1].t > 3 * T) return 'the bottom ball does not go round';
    return `T = ${T.toFixed(3)} s for one turn of the bottom ball: 2π/T = ${(2 / T).toFixed(2)}π rad/s`;
  }

  // ---- the loop ------------------------------------------------------------------------------
  let last = null;
  const meter = {wall: 0, sim: 0, cost: 0, frames: 0};

  function caption() {
    const p = engine.parameters();
    const w = engine.omegaM() / PI, target = engine.omegaTarget() / PI;
    const motor = Math.abs(w - target) < 1e-9 ? `held at ω_m = ${w.toFixed(2)}π rad/s`
        : `ramping to ${target.toFixed(2)}π rad/s at ${rate()} rad/s²`;
    const friction = {stick_slip: 'stick-slip', kinetic: 'kinetic-only', none: 'no'}[p.friction] || p.friction;
    const law = p.frictionLaw === 'capstan' ? 'capstan' : 'point-contact';
    $('caption').textContent =
        `Simulating the motor-driven Astrojax: string l = ${format(p.l)} m on a rod of R = ${format(1e3 * p.R)} mm, ` +
        `bead m1 = ${format(1e3 * p.m1)} g, bottom ball m2 = ${format(1e3 * p.m2)} g, contact distance ` +
        `d = ${format(1e2 * p.d)} cm, drag c_D = ${format(1e3 * p.cD)} g/s, ${friction} ${law} friction ` +
        `(μ_s = ${format(p.muS)}, μ_k = ${format(p.muK)}), ${p.clutch ? 'tie clutch' : 'rigid tie'}, g = ${p.g} m/s². ` +
        `Started ${{rest: 'from rest', table1: 'on the paper\'s Table 1 orbit', locked: 'on the locked orbit'}[startKind]}` +
        ` at ${(startOmega / PI).toFixed(2)}π rad/s; motor ${motor}.`;
  }

  function status(verdict) {
    $('simtime').textContent = `${engine.time().toFixed(2)} s simulated`;
    const w = engine.omegaM() / PI, target = engine.omegaTarget() / PI;
    $('omega').textContent = `${w.toFixed(2)}π rad/s` +
        (Math.abs(w - target) > 1e-9 ? ` → ${target.toFixed(2)}π` : ' (held)');
    if (verdict) {
      const wb = Number.isFinite(verdict.omegaBall) ? `, ω_ball = ${(verdict.omegaBall / PI).toFixed(2)}π rad/s` : '';
      const el = $('verdict');
      el.textContent = verdict.cls === 'none' ? 'waiting for a 5 s window' : `${verdict.cls}${wb}`;
      el.style.color = CLASS_COLOR[verdict.cls] || '#333';
      el.title = verdict.reason;
    }
    $('period').textContent = periodText();
  }

  function measure(dtWall, want, cost) {
    meter.wall += dtWall; meter.sim += want; meter.cost += cost; meter.frames += 1;
    if (meter.wall < 1.0) return;
    const speed = +$('speed').value;
    const factor = meter.sim / meter.wall, fps = meter.frames / meter.wall, capacity = meter.sim / meter.cost;
    live.realtime = {factor, fps, capacity, speed, msPerFrame: 1e3 * meter.cost / meter.frames};
    $('realtime').textContent = `${factor.toFixed(2)} s simulated per second at ${fps.toFixed(0)} frames/s ` +
        `(the engine takes ${(1e3 * meter.cost / meter.frames).toFixed(1)} ms a frame: up to ${capacity.toFixed(0)}× real time)`;
    const behind = factor < 0.95 * speed || fps < 50;
    const b = $('behind');
    b.hidden = !behind;
    const slow = factor < 0.95 * speed ? `the motion runs at ${factor.toFixed(2)}× real time instead of ${speed}×` : '';
    const jerky = fps < 50 ? `it draws ${fps.toFixed(0)} frames a second instead of 60` : '';
    b.textContent = behind ? `This computer cannot keep up: ${[slow, jerky].filter((x) => x).join(', and ')}.` : '';
    meter.wall = meter.sim = meter.cost = meter.frames = 0;
  }

  function frame(now) {
    const dtWall = last === null ? 0 : Math.min((now - last) / 1000, 0.1);
    last = now;
    const want = dtWall * +$('speed').value;
    let cost = 0, verdict = null;
    if (!failed && want > 0) {
      const t0 = performance.now();
      if (!engine.advance(want)) {
        failed = true;
        showError(`the integration failed: ${engine.failure()} (start again)`);
      }
      timePeriods(engine.recentSamples());
      if (engine.time() >= nextClassify) {
        verdict = engine.classify();
        live.verdict = verdict;
        nextClassify = engine.time() + CLASSIFY_EVERY;
        if (verdict.cls !== 'none' && Number.isFinite(verdict.omegaBall))
          live.trace.push({t: engine.time(), wm: verdict.omegaM / PI, wb: verdict.omegaBall / PI, cls: verdict.cls});
      }
      cost = (performance.now() - t0) / 1000;
    }
    measure(dtWall, failed ? 0 : want, cost);
    const pos = engine.positions(), mode = engine.mode();
    drawFront(pos, mode, engine.time());
    drawBottom(pos, mode, engine.time());
    drawEnergy();
    if (verdict) drawTrace();
    status(verdict);
    caption();
    requestAnimationFrame(frame);
  }

  window.addEventListener('error', (e) => live.consoleErrors.push(String(e.message)));

  createAstrojax().then((Module) => {
    engine = new Module.Engine();
    buildSliders();
    wireControls();
    const problems = readAddress();
    syncControls();
    const ok = configure(null);
    if (!ok) overrides = {};  // the engine runs the scene's own model
    start(startKind);
    if (problems.length) showError(problems.join('; '));
    else if (!ok) showError(live.errors[live.errors.length - 1]);
    drawTrace();
    live.ready = true;
    requestAnimationFrame(frame);
  });
})();
