// c3dfix viewer: plays marker data packed by `c3dfix view` on a canvas with its own small
// perspective projection. Everything it needs is in this page.
(function () {
  'use strict';
  const selftest = /[?&]selftest=1\b/.test(location.search);
  const errors = [];
  if (selftest) {
    const orig = console.error.bind(console);
    console.error = function () {
      errors.push(Array.prototype.map.call(arguments, String).join(' '));
      orig.apply(console, arguments);
    };
    window.addEventListener('error', (e) => errors.push(String(e.message)));
  }

  const $ = (id) => document.getElementById(id);
  const meta = JSON.parse($('meta').textContent);
  function bytes(id) {
    const s = atob($(id).textContent.trim());
    const u = new Uint8Array(s.length);
    for (let i = 0; i < s.length; i++) u[i] = s.charCodeAt(i);
    return u;
  }
  // Little-endian floats, as every browser platform stores them.
  const xyz = new Float32Array(bytes('xyz').buffer);
  const flags = bytes('flags');
  const origBytes = bytes('origxyz');
  const oxyz = origBytes.length ? new Float32Array(origBytes.buffer) : null;
  const N = meta.frames, M = meta.count;
  const FILLED = 2;
  // Force plates: outlines, and per frame and plate the COP then the force (NaN: unloaded).
  const plates = meta.plates || [];
  const P = plates.length;
  const forceBytes = bytes('forces');
  const fdata = forceBytes.length ? new Float32Array(forceBytes.buffer) : null;

  // Data axes → view axes (view z is up); a cyclic permutation keeps the handedness.
  const perm = meta.up === 2 ? [0, 1, 2] : meta.up === 1 ? [2, 0, 1] : [1, 2, 0];
  // A lab whose up is an axis' negative direction is turned over (half a turn about the view's
  // x), which keeps the handedness too.
  const sgn = meta.up_positive === false ? [1, -1, -1] : [1, 1, 1];
  const axisNames = ['X', 'Y', 'Z'];
  function get(arr, f, m, out) {
    const i = (f * M + m) * 3;
    out[0] = arr[i + perm[0]] * sgn[0]; out[1] = arr[i + perm[1]] * sgn[1]; out[2] = arr[i + perm[2]] * sgn[2];
    return out[0] === out[0];
  }

  const plateCorners = plates.map((p) => p.corners.map((c) => [c[perm[0]] * sgn[0], c[perm[1]] * sgn[1], c[perm[2]] * sgn[2]]));
  // Plate k at frame f into cop and force (view axes); false where the COP is undefined.
  function plateAt(f, k, cop, force) {
    if (!fdata) return false;
    const i = (f * P + k) * 6;
    for (let a = 0; a < 3; a++) { cop[a] = fdata[i + perm[a]] * sgn[a]; force[a] = fdata[i + 3 + perm[a]] * sgn[a]; }
    return cop[0] === cop[0] && force[0] === force[0];
  }

  // Last valid frame of each marker at each frame (-1: none yet): where gaps are ghosted.
  const lastValid = new Int32Array(N * M);
  for (let m = 0; m < M; m++) {
    let lv = -1;
    for (let f = 0; f < N; f++) {
      const i = f * M + m;
      if (xyz[i * 3] === xyz[i * 3]) lv = f;
      lastValid[i] = lv;
    }
  }

  // Scene bounds from the valid samples.
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  const tmp = [0, 0, 0], tmp2 = [0, 0, 0];
  const stride = Math.max(1, Math.floor(N / 500));
  for (let f = 0; f < N; f += stride) {
    for (let m = 0; m < M; m++) {
      if (!get(xyz, f, m, tmp)) continue;
      for (let a = 0; a < 3; a++) { lo[a] = Math.min(lo[a], tmp[a]); hi[a] = Math.max(hi[a], tmp[a]); }
    }
  }
  if (!(lo[0] <= hi[0])) { lo.fill(-1000); hi.fill(1000); }
  const size = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-6);
  const floor = lo[2] >= -0.1 * size && lo[2] <= 0.3 * size ? 0 : lo[2];
  const spacing = (function () {
    const raw = size / 10, p = Math.pow(10, Math.floor(Math.log10(raw)));
    return raw / p < 2 ? p : raw / p < 5 ? 2 * p : 5 * p;
  })();
  const grid = {
    x0: Math.floor(Math.min(lo[0], 0) / spacing - 1) * spacing,
    x1: Math.ceil(Math.max(hi[0], 0) / spacing + 1) * spacing,
    y0: Math.floor(Math.min(lo[1], 0) / spacing - 1) * spacing,
    y1: Math.ceil(Math.max(hi[1], 0) / spacing + 1) * spacing,
  };

  const home = () => ({
    target: [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2],
    yaw: -Math.PI / 3, pitch: 0.3, dist: size * 1.15,
  });
  let cam = home();

  const canvas = $('view');
  const ctx = canvas.getContext('2d');
  let W = 1, H = 1, dpr = 1;
  function resize() {
    dpr = window.devicePixelRatio || 1;
    W = canvas.clientWidth || 800; H = canvas.clientHeight || 600;
    canvas.width = Math.round(W * dpr); canvas.height = Math.round(H * dpr);
    draw();
  }

  // Camera basis, rebuilt before each drawing.
  let eye = [0, 0, 0], fw = [0, 0, 0], rt = [0, 0, 0], upv = [0, 0, 0], focal = 1;
  function setupCamera() {
    const cp = Math.cos(cam.pitch), sp = Math.sin(cam.pitch);
    const d = [cp * Math.cos(cam.yaw), cp * Math.sin(cam.yaw), sp];
    eye = [cam.target[0] + d[0] * cam.dist, cam.target[1] + d[1] * cam.dist, cam.target[2] + d[2] * cam.dist];
    fw = [-d[0], -d[1], -d[2]];
    rt = [fw[1], -fw[0], 0];
    const rl = Math.hypot(rt[0], rt[1]) || 1; rt[0] /= rl; rt[1] /= rl;
    upv = [rt[1] * fw[2] - rt[2] * fw[1], rt[2] * fw[0] - rt[0] * fw[2], rt[0] * fw[1] - rt[1] * fw[0]];
    focal = 0.5 * H / Math.tan(Math.PI / 8);
  }
  // Screen position and depth, or null behind the camera.
  function project(p) {
    const dx = p[0] - eye[0], dy = p[1] - eye[1], dz = p[2] - eye[2];
    const z = dx * fw[0] + dy * fw[1] + dz * fw[2];
    if (z < size * 0.01) return null;
    const x = dx * rt[0] + dy * rt[1] + dz * rt[2];
    const y = dx * upv[0] + dy * upv[1] + dz * upv[2];
    return [W / 2 + focal * x / z, H / 2 - focal * y / z, z];
  }
  function line(a, b) {
    const p = project(a), q = project(b);
    if (!p || !q) return;
    ctx.moveTo(p[0], p[1]); ctx.lineTo(q[0], q[1]);
  }

  let frame = 0, playing = false, dir = 1, speed = 1, acc = 0, last = null;
  let showLabels = false, showSticks = true, showOrig = true, follow = false, hover = -1;
  let showPlates = true, platesDrawn = 0, arrowsDrawn = 0;
  // Zoom to the subject's own size (the extent of the current frame's points).
  function frameSize() {
    const a = [Infinity, Infinity, Infinity], b = [-Infinity, -Infinity, -Infinity], p = [0, 0, 0];
    for (let m = 0; m < M; m++) {
      if (!get(xyz, frame, m, p)) continue;
      for (let k = 0; k < 3; k++) { a[k] = Math.min(a[k], p[k]); b[k] = Math.max(b[k], p[k]); }
    }
    const s = Math.max(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    return s > 0 && isFinite(s) ? s : size;
  }
  // Traced points; a skeleton starts with its End Sites traced.
  const traced = new Set(meta.traced || []);
  const skeleton = meta.kind === 'bvh';
  const isEnd = skeleton ? new Set(meta.traced || []) : new Set();
  let drawn = 0, screen = [];

  const COL = { plate: '#8c564b', plateFill: 'rgba(140,86,75,0.10)', grf: '#e377c2', end: '#9467bd', shadow: 'rgba(0,0,0,0.12)', marker: '#1f77b4', filled: '#ff7f0e', orig: '#2ca02c', err: '#d62728', ghost: '#999', stick: '#555' };

  function drawGrid() {
    ctx.lineWidth = 1;
    ctx.strokeStyle = '#d8d8d4';
    ctx.beginPath();
    for (let x = grid.x0; x <= grid.x1 + 1e-9; x += spacing) line([x, grid.y0, floor], [x, grid.y1, floor]);
    for (let y = grid.y0; y <= grid.y1 + 1e-9; y += spacing) line([grid.x0, y, floor], [grid.x1, y, floor]);
    ctx.stroke();
    const o = [0, 0, floor], L = spacing * 2;
    const cols = ['#d62728', '#2ca02c', '#1f77b4'];
    ctx.lineWidth = 2;
    ctx.font = '12px sans-serif';
    for (let a = 0; a < 3; a++) {
      const e = o.slice(); e[a] += L;
      ctx.strokeStyle = cols[a];
      ctx.beginPath(); line(o, e); ctx.stroke();
      const p = project(e);
      if (p) { ctx.fillStyle = cols[a]; ctx.fillText((sgn[a] < 0 ? '-' : '') + axisNames[perm[a]], p[0] + 3, p[1] - 3); }
    }
  }

  // Each plate's outline, and the ground reaction as an arrow from the COP along the force,
  // meta.force_scale data units per newton; no arrow where the plate is unloaded.
  function drawPlates(f) {
    platesDrawn = 0; arrowsDrawn = 0;
    if (!P || !showPlates) return;
    ctx.lineWidth = 1.5; ctx.strokeStyle = COL.plate; ctx.fillStyle = COL.plateFill;
    for (const corners of plateCorners) {
      const q = corners.map(project);
      if (q.some((p) => !p)) continue;
      ctx.beginPath(); ctx.moveTo(q[0][0], q[0][1]);
      for (let k = 1; k < 4; k++) ctx.lineTo(q[k][0], q[k][1]);
      ctx.closePath(); ctx.fill(); ctx.stroke();
      platesDrawn++;
    }
    const cop = [0, 0, 0], force = [0, 0, 0];
    ctx.strokeStyle = COL.grf; ctx.fillStyle = COL.grf; ctx.lineWidth = 2.5;
    for (let k = 0; k < P; k++) {
      if (!plateAt(f, k, cop, force)) continue;
      const s = meta.force_scale;
      const a = project(cop), b = project([cop[0] + force[0] * s, cop[1] + force[1] * s, cop[2] + force[2] * s]);
      if (!a || !b) continue;
      ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke();
      const t = Math.atan2(b[1] - a[1], b[0] - a[0]), h = 9;
      ctx.beginPath(); ctx.moveTo(b[0], b[1]);
      ctx.lineTo(b[0] - h * Math.cos(t - 0.4), b[1] - h * Math.sin(t - 0.4));
      ctx.lineTo(b[0] - h * Math.cos(t + 0.4), b[1] - h * Math.sin(t + 0.4));
      ctx.closePath(); ctx.fill();
      ctx.beginPath(); ctx.arc(a[0], a[1], 3, 0, 2 * Math.PI); ctx.fill();
      arrowsDrawn++;
    }
  }

  function drawTraces() {
    if (!traced.size) return;
    const step = Math.max(1, Math.ceil(N / 2000));
    ctx.lineWidth = 1.5;
    for (const m of traced) {
      ctx.strokeStyle = 'rgba(148,103,189,0.8)';
      ctx.beginPath();
      let pen = false;
      for (let f = 0; f < N; f += step) {
        const p = get(xyz, f, m, tmp) ? project(tmp) : null;
        if (!p) { pen = false; continue; }
        if (pen) ctx.lineTo(p[0], p[1]); else ctx.moveTo(p[0], p[1]);
        pen = true;
      }
      ctx.stroke();
    }
  }

  function draw() {
    if (!ctx) return;
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.fillStyle = '#f4f4f2';
    ctx.fillRect(0, 0, W, H);
    const f = frame;
    const pos = new Array(M);
    for (let m = 0; m < M; m++) { const p = [0, 0, 0]; pos[m] = get(xyz, f, m, p) ? p : null; }
    // Follow: aim at this frame's centroid, so a walking subject stays in the middle.
    if (follow) {
      const c = [0, 0, 0]; let n = 0;
      for (const p of pos) if (p) { c[0] += p[0]; c[1] += p[1]; c[2] += p[2]; n++; }
      if (n) cam.target = [c[0] / n, c[1] / n, c[2] / n];
    }
    setupCamera();
    drawGrid();
    drawPlates(f);
    drawTraces();
    // The sticks' shadow on the floor, straight down: shows stance and where the feet are.
    if (showSticks && meta.shadow) {
      ctx.lineWidth = 3; ctx.strokeStyle = COL.shadow; ctx.beginPath();
      for (const [a, b] of meta.sticks) {
        if (pos[a] && pos[b]) line([pos[a][0], pos[a][1], floor], [pos[b][0], pos[b][1], floor]);
      }
      ctx.stroke();
    }
    // Sticks.
    if (showSticks) {
      ctx.lineWidth = 2; ctx.strokeStyle = COL.stick; ctx.beginPath();
      for (const [a, b] of meta.sticks) if (pos[a] && pos[b]) line(pos[a], pos[b]);
      ctx.stroke();
    }
    // Original and error vectors.
    let errSum = 0, errN = 0;
    const opos = new Array(M).fill(null);
    if (oxyz) {
      for (let m = 0; m < M; m++) { const p = [0, 0, 0]; if (get(oxyz, f, m, p)) opos[m] = p; }
      for (let m = 0; m < M; m++) {
        if (pos[m] && opos[m]) {
          errSum += Math.hypot(pos[m][0] - opos[m][0], pos[m][1] - opos[m][1], pos[m][2] - opos[m][2]);
          errN++;
        }
      }
      if (showOrig) {
        ctx.lineWidth = 1; ctx.strokeStyle = 'rgba(44,160,44,0.6)'; ctx.setLineDash([4, 3]); ctx.beginPath();
        if (showSticks) for (const [a, b] of meta.sticks) if (opos[a] && opos[b]) line(opos[a], opos[b]);
        ctx.stroke(); ctx.setLineDash([]);
        ctx.lineWidth = 1.5; ctx.strokeStyle = COL.err; ctx.beginPath();
        for (let m = 0; m < M; m++) if (pos[m] && opos[m]) line(pos[m], opos[m]);
        ctx.stroke();
        for (let m = 0; m < M; m++) {
          const p = opos[m] && project(opos[m]);
          if (!p) continue;
          ctx.strokeStyle = COL.orig; ctx.lineWidth = 1.5;
          ctx.beginPath(); ctx.arc(p[0], p[1], radius(p[2]) + 1, 0, 2 * Math.PI); ctx.stroke();
        }
      }
    }
    // Markers, far ones first; ghosts where a marker is missing.
    screen = [];
    for (let m = 0; m < M; m++) {
      if (pos[m]) {
        const p = project(pos[m]);
        if (p) screen.push({ m, p, ghost: false, filled: (flags[f * M + m] & FILLED) !== 0 });
      } else {
        const lv = lastValid[f * M + m];
        if (lv >= 0 && get(xyz, lv, m, tmp2)) {
          const p = project(tmp2);
          if (p) screen.push({ m, p, ghost: true, filled: false });
        }
      }
    }
    screen.sort((a, b) => b.p[2] - a.p[2]);
    drawn = 0;
    for (const s of screen) {
      const r = radius(s.p[2]);
      ctx.beginPath(); ctx.arc(s.p[0], s.p[1], r, 0, 2 * Math.PI);
      if (s.ghost) {
        ctx.setLineDash([2, 2]); ctx.strokeStyle = COL.ghost; ctx.lineWidth = 1; ctx.stroke(); ctx.setLineDash([]);
      } else {
        ctx.fillStyle = s.filled ? COL.filled : isEnd.has(s.m) ? COL.end : COL.marker; ctx.fill();
        ctx.strokeStyle = '#fff'; ctx.lineWidth = 0.75; ctx.stroke();
        drawn++;
      }
      if (traced.has(s.m)) {
        ctx.beginPath(); ctx.arc(s.p[0], s.p[1], r + 3, 0, 2 * Math.PI);
        ctx.strokeStyle = '#9467bd'; ctx.lineWidth = 1.5; ctx.stroke();
      }
    }
    if (showLabels) {
      ctx.font = '11px sans-serif'; ctx.fillStyle = '#333';
      for (const s of screen) ctx.fillText(meta.labels[s.m], s.p[0] + radius(s.p[2]) + 2, s.p[1] - 2);
    }
    updateText(errN ? errSum / errN : null);
  }
  function radius(z) { return Math.max(2, Math.min(9, focal * size * 0.007 / z)); }

  const frameEl = $('frame'), slider = $('slider'), hud = $('hud');
  slider.max = String(Math.max(0, N - 1));
  function updateText(meanErr) {
    // A C3D frame n is at (n - 1) / rate, the file's one time base (EVENT times, exports).
    const t0 = skeleton ? 0 : Math.max(meta.first_frame - 1, 0);
    const t = meta.rate > 0 ? ((t0 + frame) / meta.rate).toFixed(3) + ' s' : '';
    frameEl.textContent = 'Frame ' + (meta.first_frame + frame) + ' (' + (frame + 1) + '/' + N + ') ' + t;
    slider.value = String(frame);
    let h = '<b></b>';
    const hz = Math.round(meta.rate * 1000) / 1000;
    if (skeleton) {
      h += ' · ' + (M - isEnd.size) + ' joints, ' + isEnd.size + ' End Sites, ' + hz + ' Hz';
      h += '<br><span class="k" style="background:' + COL.marker + '"></span>joint';
      h += '<span class="k" style="background:' + COL.end + '"></span>End Site (traced)';
    } else {
      h += ' · ' + M + ' markers, ' + hz + ' Hz';
      h += '<br><span class="k" style="background:' + COL.marker + '"></span>measured';
      if (meta.fills_marked !== false) h += '<span class="k" style="background:' + COL.filled + '"></span>filled (residual 0)';
      h += '<span class="k" style="border:1px dashed ' + COL.ghost + '"></span>missing (last seen)';
    }
    if (P) {
      h += '<br><span class="k" style="border:2px solid ' + COL.plate + ';border-radius:0"></span>' + P + ' force plate' + (P === 1 ? '' : 's');
      h += '<span class="k" style="background:' + COL.grf + '"></span>ground reaction (from the COP)';
    }
    if (oxyz) {
      h += '<span class="k" style="border:2px solid ' + COL.orig + '"></span>original';
      h += '<br>mean error this frame: <b id="err"></b>';
    }
    hud.innerHTML = h;
    hud.firstChild.textContent = meta.title;
    const e = $('err');
    if (e) e.textContent = meanErr === null ? '—' : meanErr.toFixed(2) + ' ' + meta.units;
  }

  function setFrame(n) {
    n = Math.round(Number(n));
    if (!(n >= 0)) n = 0;
    frame = Math.min(Math.max(0, N - 1), n);
    draw();
  }
  function tick(now) {
    if (!playing) return;
    if (last !== null) acc += (now - last) / 1000 * meta.rate * speed;
    last = now;
    const steps = Math.floor(acc);
    if (steps > 0 && N > 0) {
      acc -= steps;
      setFrame((((frame + dir * steps) % N) + N) % N);
    }
    schedule();
  }
  // Animation frames pace playback; a timer stands in where they do not come (a hidden tab,
  // a headless browser), whichever comes first runs the step.
  let ticket = 0;
  function schedule() {
    const id = ++ticket;
    const go = () => { if (id === ticket) { ticket++; tick(performance.now()); } };
    requestAnimationFrame(go);
    setTimeout(go, 40);
  }
  function play(reverse) {
    dir = reverse ? -1 : 1;
    if (!playing) { playing = true; last = null; acc = 0; schedule(); }
    buttons();
  }
  function pause() { playing = false; buttons(); }
  function buttons() {
    $('play').textContent = playing && dir > 0 ? '||' : '▶';
    $('rev').textContent = playing && dir < 0 ? '||' : '◀';
  }
  function toggle(reverse) {
    if (playing && (dir < 0) === !!reverse) pause(); else play(reverse);
  }
  function step(d) { pause(); setFrame(Math.min(N - 1, Math.max(0, frame + d))); }

  $('play').onclick = () => toggle(false);
  $('rev').onclick = () => toggle(true);
  $('back').onclick = () => step(-1);
  $('fwd').onclick = () => step(1);
  $('speed').onchange = (e) => { speed = Number(e.target.value) || 1; };
  slider.addEventListener('input', () => setFrame(slider.value));
  // Events on the time bar: a tick at each event's frame (the file's own above, detected ones
  // below, in another colour), its short label beside it, the full wording as a tooltip; a
  // click goes to the event's frame. The slider's thumb centre runs from half a thumb in
  // from each end, so the ticks are laid on that span.
  const events = meta.events || [];
  const THUMB = 16;
  const markFrac = (index) => (N > 1 ? Math.min(1, Math.max(0, index / (N - 1))) : 0);
  for (const e of events) {
    const el = document.createElement('span');
    el.className = e.detected ? 'ev det' : 'ev';
    el.style.left = 'calc(' + THUMB / 2 + 'px + (100% - ' + THUMB + 'px) * ' + markFrac(e.index) + ')';
    el.title = e.full;
    const t = document.createElement('span');
    t.textContent = e.short;
    el.appendChild(t);
    el.addEventListener('click', () => { pause(); setFrame(e.index); });
    $('marks').appendChild(el);
  }
  $('labels').onchange = (e) => { showLabels = e.target.checked; draw(); };
  $('sticks').onchange = (e) => { showSticks = e.target.checked; draw(); };
  $('orig').onchange = (e) => { showOrig = e.target.checked; draw(); };
  $('follow').onchange = (e) => {
    follow = e.target.checked;
    cam = follow ? { ...cam, dist: frameSize() * 2.2 } : home();
    draw();
  };
  if (!oxyz) $('origwrap').style.display = 'none';
  if (!P) $('plateswrap').style.display = 'none';
  $('plates').onchange = (e) => { showPlates = e.target.checked; draw(); };
  $('reset').onclick = () => { cam = home(); draw(); };

  // Marker list for traces.
  const list = $('list');
  meta.labels.forEach((l, m) => {
    const lab = document.createElement('label');
    const box = document.createElement('input');
    box.type = 'checkbox'; box.dataset.m = String(m);
    box.onchange = () => { if (box.checked) traced.add(m); else traced.delete(m); draw(); };
    lab.appendChild(box); lab.appendChild(document.createTextNode(' ' + l));
    list.appendChild(lab);
  });
  function syncList() {
    for (const b of list.querySelectorAll('input')) b.checked = traced.has(Number(b.dataset.m));
  }
  syncList();
  $('markers').onclick = () => { list.style.display = list.style.display === 'block' ? 'none' : 'block'; };

  // Camera: drag to orbit, shift or right drag to pan, wheel to zoom; click a marker to trace it.
  let drag = null;
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('mousedown', (e) => {
    drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2, moved: false };
    canvas.style.cursor = 'grabbing';
  });
  window.addEventListener('mouseup', (e) => {
    if (drag && !drag.moved) {
      const m = pick(e);
      if (m >= 0) { if (traced.has(m)) traced.delete(m); else traced.add(m); syncList(); draw(); }
    }
    drag = null; canvas.style.cursor = 'grab';
  });
  window.addEventListener('mousemove', (e) => {
    if (drag) {
      const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
      if (Math.abs(dx) + Math.abs(dy) > 2) drag.moved = true;
      drag.x = e.clientX; drag.y = e.clientY;
      if (drag.pan) {
        const k = cam.dist / focal;
        for (let a = 0; a < 3; a++) cam.target[a] += (-dx * rt[a] + dy * upv[a]) * k;
      } else {
        cam.yaw -= dx * 0.008;
        cam.pitch = Math.max(-1.5, Math.min(1.5, cam.pitch + dy * 0.008));
      }
      draw();
      return;
    }
    if (e.target !== canvas) return;
    const m = pick(e);
    const tip = $('tip');
    if (m !== hover) {
      hover = m;
      if (m >= 0) { tip.textContent = meta.labels[m]; tip.style.display = 'block'; } else tip.style.display = 'none';
    }
    if (m >= 0) { tip.style.left = e.clientX + 12 + 'px'; tip.style.top = e.clientY + 8 + 'px'; }
  });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    cam.dist = Math.max(size * 0.05, Math.min(size * 50, cam.dist * Math.exp(e.deltaY * 0.001)));
    draw();
  }, { passive: false });
  function pick(e) {
    const r = canvas.getBoundingClientRect();
    const x = e.clientX - r.left, y = e.clientY - r.top;
    let best = -1, bd = 100;
    for (const s of screen) {
      const d = (s.p[0] - x) ** 2 + (s.p[1] - y) ** 2;
      if (d < bd) { bd = d; best = s.m; }
    }
    return best;
  }

  window.addEventListener('keydown', (e) => {
    const t = e.target;
    if (t && (t.tagName === 'SELECT' || (t.tagName === 'INPUT' && t.type === 'range' && e.key.startsWith('Arrow')))) return;
    const big = e.shiftKey ? 10 : 1;
    switch (e.key) {
      case ' ': toggle(false); break;
      case 'ArrowRight': step(big); break;
      case 'ArrowLeft': step(-big); break;
      case 'ArrowUp': case 'ArrowDown': {
        const s = $('speed'), i = s.selectedIndex + (e.key === 'ArrowUp' ? 1 : -1);
        s.selectedIndex = Math.max(0, Math.min(s.options.length - 1, i));
        speed = Number(s.value); break;
      }
      case 'r': case 'R': toggle(true); break;
      case 'l': case 'L': $('labels').click(); break;
      case 'c': case 'C': $('follow').click(); break;
      case 'f': case 'F': cam = home(); draw(); break;
      case 'Home': step(-N); break;
      case 'End': step(N); break;
      default: return;
    }
    e.preventDefault();
    if (t && t.blur && t !== document.body) t.blur();
  });
  window.addEventListener('resize', resize);

  window.c3dfixViewer = {
    frame: () => frame,
    frames: () => N,
    play: () => play(false),
    pause: pause,
    setFrame: setFrame,
    drawn: () => drawn,
    platesDrawn: () => platesDrawn,
    arrowsDrawn: () => arrowsDrawn,
  };
  resize();

  // ?follow=1 opens the page following the subject (for links and screenshots).
  if (/[?&]follow=1\b/.test(location.search)) $('follow').click();
  // ?frame=K opens the page at the file's frame K (numbered as the file numbers frames).
  // Otherwise it opens at the first frame where a marker is seen: a trial recorded before
  // the subject walks into view would open on an empty floor.
  const at = /[?&]frame=(\d+)/.exec(location.search);
  if (at) setFrame(Number(at[1]) - meta.first_frame);
  else {
    const seen = (f) => { for (let m = 0; m < M; m++) if (lastValid[f * M + m] >= 0) return true; return false; };
    let f = 0;
    while (f < N && !seen(f)) f++;
    if (f > 0 && f < N) setFrame(f);
  }

  // Whether the scene stands upright, read through what the renderer draws with (the page's
  // axis mapping, its camera and projection): `screen_up` is the lab direction (raw file
  // axes, e.g. '+z') that the home view shows as straight up on the screen, `screen_up_share`
  // how much of that direction's screen step is vertical; and, over the frames the bounds
  // are read from, how the markers lie against the floor grid: `below_floor`, the share of
  // their samples more than 5 % of the scene's size under it, and `lowest_p50`, the median
  // over frames of the lowest marker's height above it, in scene sizes.
  function upright(r) {
    cam = home();
    setupCamera();
    const c = cam.target, p0 = project(c), unit = new Float32Array(3), v = [0, 0, 0];
    let best = null, bestDy = 0, bestShare = 0;
    for (let a = 0; a < 3; a++) {
      for (const s of [1, -1]) {
        unit.fill(0); unit[a] = s;
        get(unit, 0, 0, v);
        const q = project([c[0] + v[0] * size * 0.1, c[1] + v[1] * size * 0.1, c[2] + v[2] * size * 0.1]);
        if (!p0 || !q) continue;
        const dx = q[0] - p0[0], dy = p0[1] - q[1];
        if (dy > bestDy) { bestDy = dy; best = (s > 0 ? '+' : '-') + 'xyz'[a]; bestShare = dy / Math.hypot(dx, dy); }
      }
    }
    r.screen_up = best;
    r.screen_up_share = bestShare;
    const lows = [];
    let samples = 0, below = 0;
    for (let f = 0; f < N; f += stride) {
      let low = Infinity;
      for (let m = 0; m < M; m++) {
        if (!get(xyz, f, m, tmp)) continue;
        const h = (tmp[2] - floor) / size;
        samples++;
        if (h < -0.05) below++;
        low = Math.min(low, h);
      }
      if (low < Infinity) lows.push(low);
    }
    lows.sort((a, b) => a - b);
    r.floor = floor;
    r.size = size;
    r.samples_checked = samples;
    r.below_floor = samples ? below / samples : null;
    r.lowest_p50 = lows.length ? lows[Math.floor(lows.length / 2)] : null;
  }

  // Self-test (?selftest=1): plays, moves the slider and reports into the page, for the
  // project's browser test.
  if (selftest) {
    const r = { errors: errors, opened_at: frame + meta.first_frame };
    const out = document.createElement('pre');
    out.id = 'selftest';
    const px = () => {
      const d = ctx.getImageData(0, 0, canvas.width, canvas.height).data;
      let n = 0;
      for (let i = 0; i < d.length; i += 4) if (Math.abs(d[i] - 244) + Math.abs(d[i + 1] - 244) + Math.abs(d[i + 2] - 242) > 30) n++;
      return n;
    };
    setTimeout(() => {
      r.frames = N;
      r.markers_drawn = drawn;
      r.painted_pixels = px();
      setFrame(0);
      play();
      setTimeout(() => {
        r.played_to = frame;
        r.counter_after_play = frameEl.textContent;
        pause();
        const target = Math.min(7, N - 1);
        slider.value = String(target);
        slider.dispatchEvent(new Event('input'));
        r.slider_frame = frame;
        r.counter_after_slider = frameEl.textContent;
        play(true);
        setTimeout(() => {
          r.reversed_to = frame;
          pause();
          // The plates: every outline drawn; an arrow on the first loaded frame, none on a
          // frame where no plate is loaded.
          const cop = [0, 0, 0], force = [0, 0, 0];
          const loaded = (f) => { for (let k = 0; k < P; k++) if (plateAt(f, k, cop, force)) return true; return false; };
          r.plates = P;
          r.loaded_frame = -1; r.unloaded_frame = -1;
          for (let f = 0; f < N && (r.loaded_frame < 0 || r.unloaded_frame < 0); f++) {
            if (loaded(f)) { if (r.loaded_frame < 0) r.loaded_frame = f; } else if (r.unloaded_frame < 0) r.unloaded_frame = f;
          }
          if (r.loaded_frame >= 0) { setFrame(r.loaded_frame); r.plates_drawn = platesDrawn; r.arrows_drawn = arrowsDrawn; }
          if (r.unloaded_frame >= 0) { setFrame(r.unloaded_frame); r.arrows_unloaded = arrowsDrawn; }
          const platesOk = P === 0 || (r.plates_drawn === P && r.arrows_drawn > 0 && !(r.arrows_unloaded > 0));
          // Markers at a third of the trial as well: a trial may begin with every marker
          // missing (the c3d.org plate samples do), which is no fault of the page.
          // Events: one tick per event, each where the slider's thumb stands at the
          // event's frame (within 3 px), and a click on a tick going to that frame.
          const ticks = Array.from(document.querySelectorAll('#marks .ev'));
          const sr = slider.getBoundingClientRect();
          r.events = events.length;
          r.event_ticks = ticks.length;
          r.event_labels = ticks.map((el) => el.textContent);
          r.event_offsets = ticks.map((el, i) => {
            const x = el.getBoundingClientRect().left + 1;
            const want = sr.left + THUMB / 2 + (sr.width - THUMB) * markFrac(events[i].index);
            return Math.round((x - want) * 10) / 10;
          });
          if (ticks.length) {
            const k = Math.floor(ticks.length / 2);
            ticks[k].click();
            r.event_clicked = Math.round(events[k].index);
            r.frame_after_event_click = frame;
          }
          const eventsOk = ticks.length === events.length && r.event_offsets.every((d) => Math.abs(d) <= 3) &&
            (ticks.length === 0 || r.frame_after_event_click === r.event_clicked);
          setFrame(Math.floor(N / 3));
          r.markers_drawn_later = drawn;
          upright(r);
          r.ok = platesOk && eventsOk && errors.length === 0 && r.painted_pixels > 500 && Math.max(r.markers_drawn, r.markers_drawn_later) > 0 &&
            r.played_to > 0 && r.slider_frame === target && r.reversed_to !== target;
          out.textContent = JSON.stringify(r);
          document.body.appendChild(out);
          // A page opened by another (the browser test loads many at once) tells it too.
          if (window.parent !== window) window.parent.postMessage({ selftest: r }, '*');
        }, 300);
      }, 500);
    }, 100);
  }
})();
