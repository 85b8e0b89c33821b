// c3dfix report: a session's trials as a sortable, filterable table with small pictures.
// Every value from the data goes into the page as text (textContent, attributes), never
// as markup, so a label or file name cannot run anything.
(function () {
  'use strict';
  const errors = [];
  window.addEventListener('error', (e) => errors.push(String(e.message)));
  const consoleError = console.error;
  console.error = function () { errors.push(Array.from(arguments).join(' ')); consoleError.apply(console, arguments); };

  const data = JSON.parse(document.getElementById('data').textContent);
  const meta = data.meta, report = data.report, rows = report.trials, sum = report.summary;
  const PER_PAGE = 50;
  const SVG = 'http://www.w3.org/2000/svg';

  function el(tag, text, cls) {
    const e = document.createElement(tag);
    if (text !== undefined && text !== null) e.textContent = String(text);
    if (cls) e.className = cls;
    return e;
  }
  function svg(tag, attrs, text) {
    const e = document.createElementNS(SVG, tag);
    for (const k in attrs) e.setAttribute(k, String(attrs[k]));
    if (text !== undefined) e.textContent = String(text);
    return e;
  }
  function fmt(v, digits) {
    if (v === null || v === undefined) return '—';
    if (typeof v === 'number') return digits === undefined ? v.toLocaleString('en') : v.toFixed(digits);
    return String(v);
  }
  const reasons = ['too_long', 'uncertain', 'touches_edge', 'no_donors'];
  function leftOther(r) {
    let n = 0;
    for (const k in r.left_because) if (reasons.indexOf(k) < 0) n += r.left_because[k];
    return n;
  }
  function gaitValue(r, name) {
    const v = r.gait.filter((g) => g.name === name).map((g) => g.value);
    return v.length ? v.reduce((a, b) => a + b, 0) / v.length : null;
  }
  function eventsText(r) {
    return Object.keys(r.events).map((k) => k + ' ' + r.events[k]).join(' · ');
  }
  function eventsCount(r) {
    return Object.keys(r.events).reduce((a, k) => a + r.events[k], 0);
  }
  function peak(r) {
    return r.plates.length ? Math.max.apply(null, r.plates.map((p) => p.peak_force)) : null;
  }
  // key, header, value for sorting and showing, digits, title
  const columns = [
    ['name', 'trial', (r) => r.name, undefined, 'the file (a link to its view page when written)'],
    ['frames', 'frames', (r) => r.error ? null : r.frames],
    ['rate', 'Hz', (r) => r.error ? null : r.rate],
    ['markers', 'markers', (r) => r.error ? null : r.markers, undefined, 'labelled markers (model outputs and unlabelled points left out)'],
    ['unlabelled', 'unlabelled', (r) => r.error ? null : r.unlabelled, undefined, 'unlabelled points (*51, Unlabeled 3, …): counted apart, candidates for reclaiming'],
    ['missing_before', 'missing before', (r) => r.error ? null : r.missing_before, undefined, 'marker samples missing in the trial as given'],
    ['missing_after', 'missing after', (r) => r.missing_after, undefined, 'marker samples missing in the repaired copy'],
    ['filled', 'filled', (r) => r.filled, undefined, 'gaps filled'],
    ['left', 'left', (r) => r.left, undefined, 'gaps left'],
    ['too_long', 'too long', (r) => r.left === undefined ? null : (r.left_because.too_long || 0)],
    ['uncertain', 'uncertain', (r) => r.left === undefined ? null : (r.left_because.uncertain || 0)],
    ['touches_edge', 'edge', (r) => r.left === undefined ? null : (r.left_because.touches_edge || 0), undefined, 'left: at the trial\'s edge, only donors can fill'],
    ['no_donors', 'no donors', (r) => r.left === undefined ? null : (r.left_because.no_donors || 0)],
    ['other', 'other', (r) => r.left === undefined ? null : leftOther(r), undefined, 'left for another reason'],
    ['at_ends', 'at ends', (r) => r.left === undefined ? null : r.left_at_trial_end, undefined, 'gaps left at the trial\'s first or last frame'],
    ['error_mm', 'worst fill mm', (r) => r.expected_error_mm_max, 1, 'largest expected error of a fill'],
    ['swaps', 'swaps found', (r) => r.swaps_found],
    ['undone', 'undone', (r) => r.left === undefined && !r.swaps_undone ? null : r.swaps_undone + r.jumps_to_gaps, undefined, 'swaps exchanged back and jumps made gaps'],
    ['spikes', 'spikes', (r) => r.spikes],
    ['events', 'events', (r) => r.error ? null : eventsCount(r), undefined, 'events by source: file, plate, kinematics'],
    ['cadence', 'cadence', (r) => gaitValue(r, 'Cadence'), 1, 'steps/min, mean of the sides (the file\'s events)'],
    ['speed', 'speed m/s', (r) => gaitValue(r, 'Walking Speed'), 2],
    ['plates', 'plates', (r) => r.error ? null : r.plates.length],
    ['contacts', 'contacts', (r) => r.error ? null : r.plates.reduce((a, p) => a + p.contacts, 0)],
    ['peak', 'peak N', (r) => peak(r), 0, 'largest push on a plate'],
    ['refused', 'refused', (r) => r.error ? null : r.plates_refused.length, undefined, 'plates refused'],
    ['warnings', 'warnings', (r) => r.error ? null : r.warnings.length],
    ['up', 'up', (r) => r.up === undefined ? null : r.up],
    ['problem', 'first problem worth a look', (r) => r.problem || '']
  ];
  const textual = { name: 1, up: 1, problem: 1 };

  let sortKey = null, sortDir = 1, page = 0, shown = [];
  const expanded = new Set();

  function viewHref(r) {
    if (!r.view) return null;
    return encodeURIComponent(meta.views_dir) + '/' + encodeURIComponent(r.view);
  }
  function state(r) { return r.error ? 'bad' : (r.problem ? 'look' : 'clean'); }

  function renderSummary() {
    document.getElementById('title').textContent = meta.title;
    const box = document.getElementById('summary');
    const items = [
      ['trials', sum.trials], ['unreadable', sum.unreadable], ['worth a look', sum.trials - sum.clean - sum.unreadable], ['clean', sum.clean],
      ['repaired', sum.repaired], ['frames', sum.frames], ['missing before', sum.missing_before], ['missing after', sum.missing_after],
      ['gaps', sum.gaps_before], ['filled', sum.filled], ['left', sum.left], ['left at ends', sum.left_at_trial_end],
      ['worst fill mm', sum.expected_error_mm_max === null ? null : sum.expected_error_mm_max.toFixed(1)],
      ['swaps found', sum.swaps_found], ['swaps undone', sum.swaps_undone], ['jumps made gaps', sum.jumps_to_gaps], ['spikes', sum.spikes],
      ['plates', sum.plates], ['contacts', sum.contacts], ['plates refused', sum.plates_refused], ['warnings', sum.warnings]
    ];
    for (const k in sum.left_because) items.push(['left ' + k.replace(/_/g, ' '), sum.left_because[k]]);
    for (const k in sum.events) items.push(['events ' + k, sum.events[k]]);
    for (const it of items) {
      const s = el('span');
      s.appendChild(el('span', it[0] + ' '));
      s.appendChild(el('span', fmt(it[1]), 'n'));
      box.appendChild(s);
    }
    const w = document.getElementById('worst');
    if (!sum.worst.length) { w.textContent = 'Every trial is clean.'; return; }
    w.appendChild(el('b', 'Look first:'));
    const ol = el('ol');
    for (const x of sum.worst) {
      const li = el('li', rows[x.row].name + ' — ' + x.problem);
      li.addEventListener('click', () => {
        document.getElementById('filter').value = rows[x.row].name;
        document.getElementById('show').value = 'all';
        expanded.add(x.row);
        update();
      });
      ol.appendChild(li);
    }
    w.appendChild(ol);
  }

  function renderHead() {
    const head = document.getElementById('head');
    head.appendChild(el('th', ''));
    for (const c of columns) {
      const th = el('th', c[1], textual[c[0]] ? 'text' : '');
      th.dataset.key = c[0];
      if (c[4]) th.title = c[4];
      th.addEventListener('click', () => {
        if (sortKey === c[0]) sortDir = -sortDir; else { sortKey = c[0]; sortDir = textual[c[0]] ? 1 : -1; }
        page = 0;
        update();
      });
      head.appendChild(th);
    }
  }

  function compare(col) {
    return (a, b) => {
      const x = col[2](rows[a]), y = col[2](rows[b]);
      const xn = x === null || x === undefined, yn = y === null || y === undefined;
      if (xn || yn) return xn && yn ? a - b : (xn ? 1 : -1); // no value: last either way
      let d = typeof x === 'number' ? x - y : String(x).localeCompare(String(y));
      return d !== 0 ? d * sortDir : a - b;
    };
  }

  function update() {
    const q = document.getElementById('filter').value.trim().toLowerCase();
    const which = document.getElementById('show').value;
    shown = [];
    for (let i = 0; i < rows.length; i++) {
      const r = rows[i];
      if (which !== 'all' && state(r) !== which) continue;
      if (q && (r.file + ' ' + (r.problem || '') + ' ' + (r.error || '')).toLowerCase().indexOf(q) < 0) continue;
      shown.push(i);
    }
    if (sortKey) shown.sort(compare(columns.find((c) => c[0] === sortKey)));
    for (const th of document.querySelectorAll('#head th')) {
      th.classList.toggle('sorted-asc', th.dataset.key === sortKey && sortDir === 1);
      th.classList.toggle('sorted-desc', th.dataset.key === sortKey && sortDir === -1);
    }
    const pages = Math.max(1, Math.ceil(shown.length / PER_PAGE));
    page = Math.min(Math.max(page, 0), pages - 1);
    document.getElementById('page').textContent = ' page ' + (page + 1) + ' of ' + pages + ' (' + shown.length + ' trials) ';
    const body = document.getElementById('rows');
    body.textContent = '';
    for (const i of shown.slice(page * PER_PAGE, (page + 1) * PER_PAGE)) {
      body.appendChild(renderRow(i));
      if (expanded.has(i)) body.appendChild(renderDetail(i));
    }
  }

  function renderRow(i) {
    const r = rows[i];
    const tr = el('tr', undefined, state(r));
    tr.dataset.row = i;
    const t = el('td', expanded.has(i) ? '▾' : '▸', 'toggle');
    t.title = 'pictures';
    t.addEventListener('click', () => { if (expanded.has(i)) expanded.delete(i); else expanded.add(i); update(); });
    tr.appendChild(t);
    for (const c of columns) {
      const td = el('td', undefined, c[0] === 'problem' ? 'problem' : (textual[c[0]] ? 'text' : ''));
      td.dataset.key = c[0];
      const v = c[2](r);
      if (c[0] === 'name') {
        const href = viewHref(r);
        if (href) { const a = el('a', r.name); a.setAttribute('href', href); a.className = 'view'; td.appendChild(a); }
        else td.textContent = r.name;
        td.title = r.file;
      } else if (c[0] === 'problem') {
        td.textContent = r.error ? 'cannot be read: ' + r.error : (r.problem || 'clean');
      } else if (c[0] === 'events') {
        td.textContent = fmt(v); td.title = eventsText(r);
      } else {
        td.textContent = fmt(v, c[3]);
      }
      if (typeof v === 'number') td.dataset.value = String(v);
      tr.appendChild(td);
    }
    return tr;
  }

  function errorColour(e) {
    if (e === null || e === undefined) return '#1e88e5';
    if (e < 2) return '#2e7d32';
    if (e < 5) return '#c0ca33';
    if (e < 20) return '#fb8c00';
    return '#d32f2f';
  }
  function zoomable(s) {
    s.classList.add('pic');
    s.addEventListener('click', () => s.classList.toggle('big'));
    return s;
  }

  // Each marker with a sample not recorded, one bar over the frames.
  function coveragePicture(r) {
    const cov = r.pictures.coverage;
    const W = 420, left = 70, rowH = cov.length > 60 ? 3 : 6, H = Math.max(30, cov.length * rowH + 24);
    const s = svg('svg', { width: W, height: H, viewBox: '0 0 ' + W + ' ' + H });
    s.appendChild(svg('text', { x: 2, y: 10 }, 'coverage: ' + cov.length + ' of ' + r.markers + ' markers not recorded throughout'));
    const f0 = r.first_frame, n = Math.max(1, r.frames), span = W - left - 4;
    const x = (f) => left + (f - f0) / n * span;
    cov.forEach((m, k) => {
      const y = 16 + k * rowH;
      const g = svg('g');
      g.appendChild(svg('title', {}, m.label));
      if (rowH >= 6) g.appendChild(svg('text', { x: 2, y: y + rowH - 1, style: 'font-size:7px' }, m.label.slice(0, 14)));
      g.appendChild(svg('rect', { x: left, y: y, width: span, height: rowH - 1, fill: '#e8e8e8' }));
      for (const run of m.runs) {
        const rect = svg('rect', { x: x(run[0]), y: y, width: Math.max(1, x(run[1] + 1) - x(run[0])), height: rowH - 1, fill: run[2] === 0 ? '#111' : errorColour(run[3]) });
        rect.appendChild(svg('title', {}, m.label + ' frames ' + run[0] + '–' + run[1] + (run[2] === 0 ? ' missing' : ' filled' + (run[3] === null ? '' : ', expected error ' + run[3].toFixed(1) + ' mm'))));
        g.appendChild(rect);
      }
      s.appendChild(g);
    });
    return zoomable(s);
  }

  // Each plate's vertical force over time, with the events.
  function forcePicture(r) {
    const curves = r.pictures.forces, W = 420, H = 140, pad = 24;
    const s = svg('svg', { width: W, height: H, viewBox: '0 0 ' + W + ' ' + H });
    let t0 = Infinity, t1 = -Infinity, hi = 1;
    for (const c of curves) {
      t0 = Math.min(t0, c.start); t1 = Math.max(t1, c.start + c.step * Math.max(1, c.values.length - 1));
      for (const v of c.values) hi = Math.max(hi, v);
    }
    if (!(t1 > t0)) { t0 = 0; t1 = 1; }
    const x = (t) => pad + (t - t0) / (t1 - t0) * (W - pad - 4), y = (v) => H - 14 - Math.max(0, v) / hi * (H - 30);
    s.appendChild(svg('text', { x: 2, y: 10 }, 'vertical force per plate (peak ' + hi.toFixed(0) + ' N) and events'));
    const colours = ['#1f77b4', '#ff7f0e', '#2ca02c', '#9467bd', '#8c564b', '#17becf'];
    curves.forEach((c, k) => {
      const pts = c.values.map((v, j) => x(c.start + j * c.step).toFixed(1) + ',' + y(v).toFixed(1)).join(' ');
      const line = svg('polyline', { points: pts, fill: 'none', stroke: colours[k % colours.length], 'stroke-width': 1 });
      line.appendChild(svg('title', {}, 'plate ' + c.plate));
      s.appendChild(line);
    });
    for (const e of r.pictures.events) {
      if (e.time < t0 || e.time > t1) continue;
      const g = svg('g');
      g.appendChild(svg('line', { x1: x(e.time), x2: x(e.time), y1: 14, y2: H - 14, stroke: e.detected ? '#808000' : '#e377c2', 'stroke-dasharray': e.detected ? '2,2' : '' }));
      g.appendChild(svg('text', { x: x(e.time) + 1, y: e.detected ? H - 4 : 20 }, e.short));
      g.appendChild(svg('title', {}, e.short + ' ' + e.time.toFixed(3) + ' s' + (e.detected ? ' (detected)' : ' (file)')));
      s.appendChild(g);
    }
    s.appendChild(svg('text', { x: pad, y: H - 2 }, t0.toFixed(2) + ' s'));
    s.appendChild(svg('text', { x: W - 40, y: H - 2 }, t1.toFixed(2) + ' s'));
    return zoomable(s);
  }

  // One fill: x, y, z before (grey, gaps open) and after (coloured where filled).
  function fillPicture(f) {
    const W = 200, H = 110, pad = 4;
    const s = svg('svg', { width: W, height: H, viewBox: '0 0 ' + W + ' ' + H });
    const n = f.after.length;
    const title = f.label + ' ' + f.first_frame + '–' + f.last_frame + (f.expected_error_mm === undefined ? '' : ' ±' + f.expected_error_mm.toFixed(1) + ' mm');
    s.appendChild(svg('text', { x: 2, y: 10 }, title));
    const colours = ['#d62728', '#2ca02c', '#1f77b4'];
    for (let a = 0; a < 3; a++) {
      let lo = Infinity, hi = -Infinity;
      for (const p of f.before.concat(f.after)) if (p) { lo = Math.min(lo, p[a]); hi = Math.max(hi, p[a]); }
      if (!(hi > lo)) { hi = lo + 1; }
      const band = (H - 16) / 3, y0 = 14 + a * band;
      const x = (j) => pad + j / Math.max(1, n - 1) * (W - 2 * pad), y = (v) => y0 + band - 2 - (v - lo) / (hi - lo) * (band - 4);
      const path = (arr) => {
        let d = '', pen = false;
        arr.forEach((p, j) => { if (!p) { pen = false; return; } d += (pen ? 'L' : 'M') + x(j).toFixed(1) + ' ' + y(p[a]).toFixed(1); pen = true; });
        return d;
      };
      s.appendChild(svg('path', { d: path(f.after), fill: 'none', stroke: colours[a], 'stroke-width': 1.2, 'stroke-dasharray': '3,1' }));
      s.appendChild(svg('path', { d: path(f.before), fill: 'none', stroke: '#444', 'stroke-width': 1 }));
    }
    const j0 = (f.first_frame - f.window_first) / f.stride, j1 = (f.last_frame - f.window_first) / f.stride;
    const xa = pad + j0 / Math.max(1, n - 1) * (W - 2 * pad), xb = pad + j1 / Math.max(1, n - 1) * (W - 2 * pad);
    s.appendChild(svg('rect', { x: xa, y: 12, width: Math.max(1, xb - xa), height: H - 14, fill: errorColour(f.expected_error_mm), opacity: 0.15 }));
    s.appendChild(svg('title', {}, title + ': before (grey) and after (coloured, dashed)'));
    return zoomable(s);
  }

  function renderDetail(i) {
    const r = rows[i];
    const tr = el('tr', undefined, 'detail');
    const td = el('td');
    td.colSpan = columns.length + 1;
    const facts = el('ul', undefined, 'facts');
    const fact = (k, v) => { if (v !== null && v !== undefined && v !== '') facts.appendChild(el('li', k + ': ' + v)); };
    fact('file', r.file);
    fact('repaired copy', r.repaired);
    fact('error', r.error);
    fact('repaired copy error', r.repaired_error);
    fact('repair numbers from', r.repair_source === 'summary' ? 'the repair run' : (r.repair_source === 'record' ? 'the C3DFIX group of the repaired file' : null));
    fact('events', eventsText(r));
    fact('events note', r.events_note);
    fact('gait', r.gait.map((g) => g.context + ' ' + g.name + ' ' + g.value.toFixed(2) + ' ' + g.unit).join(' · '));
    fact('plates', r.plates.map((p) => p.index + ' (type ' + p.type + '): ' + p.contacts + ' contacts, peak ' + p.peak_force.toFixed(0) + ' N').join(' · '));
    for (const p of r.plates_refused || []) fact('plate refused', p);
    for (const w of r.warnings || []) fact('warning', w);
    td.appendChild(facts);
    if (!r.error) {
      const pics = el('div', undefined, 'pics');
      if (r.pictures.coverage.length) pics.appendChild(coveragePicture(r));
      if (r.pictures.forces.length) pics.appendChild(forcePicture(r));
      for (const f of r.pictures.fills) pics.appendChild(fillPicture(f));
      td.appendChild(pics);
    }
    tr.appendChild(td);
    return tr;
  }

  document.getElementById('filter').addEventListener('input', () => { page = 0; update(); });
  document.getElementById('show').addEventListener('change', () => { page = 0; update(); });
  document.getElementById('prev').addEventListener('click', () => { page--; update(); });
  document.getElementById('next').addEventListener('click', () => { page++; update(); });
  renderSummary();
  renderHead();
  update();
  const renderedMs = performance.now();

  // Self-test (?selftest=1): sorts, filters, expands and reports into the page, for the
  // browser test.
  if (/[?&]selftest=1\b/.test(location.search)) {
    const r = { rows: rows.length, errors: errors, rendered_ms: renderedMs };
    const cells = (key) => Array.from(document.querySelectorAll('#rows tr[data-row] td[data-key="' + key + '"]')).map((td) => td.dataset.value === undefined ? null : Number(td.dataset.value));
    r.shown_first_page = document.querySelectorAll('#rows tr[data-row]').length;
    const th = document.querySelector('#head th[data-key="missing_before"]');
    let t = performance.now();
    th.click();
    r.sort_ms = performance.now() - t;
    const desc = cells('missing_before').filter((v) => v !== null);
    r.sorted_desc = desc.every((v, k) => k === 0 || desc[k - 1] >= v);
    r.sorted_desc_first = desc.length ? desc[0] : null;
    th.click();
    const asc = cells('missing_before').filter((v) => v !== null);
    r.sorted_asc = asc.every((v, k) => k === 0 || asc[k - 1] <= v);
    const names = Array.from(document.querySelectorAll('#rows tr[data-row] td[data-key="name"]')).map((td) => td.textContent);
    const sortedNames = names.slice().sort((a, b) => a.localeCompare(b));
    document.querySelector('#head th[data-key="name"]').click();
    const byName = Array.from(document.querySelectorAll('#rows tr[data-row] td[data-key="name"]')).map((td) => td.textContent);
    r.sorted_by_name = JSON.stringify(byName) === JSON.stringify(sortedNames.slice(0, byName.length)) || rows.length > PER_PAGE;
    const f = document.getElementById('filter');
    const target = rows[rows.length - 1].name;
    f.value = target;
    t = performance.now();
    f.dispatchEvent(new Event('input'));
    r.filter_ms = performance.now() - t;
    const filtered = Array.from(document.querySelectorAll('#rows tr[data-row]')).map((tr) => rows[Number(tr.dataset.row)]);
    r.filter_rows = filtered.length;
    r.filter_ok = filtered.length >= 1 && filtered.every((x) => (x.file + ' ' + (x.problem || '') + ' ' + (x.error || '')).toLowerCase().indexOf(target.toLowerCase()) >= 0);
    f.value = '';
    f.dispatchEvent(new Event('input'));
    const sel = document.getElementById('show');
    sel.value = 'bad';
    sel.dispatchEvent(new Event('change'));
    r.unreadable_rows = document.querySelectorAll('#rows tr[data-row]').length;
    sel.value = 'all';
    sel.dispatchEvent(new Event('change'));
    r.pages = Math.ceil(rows.length / PER_PAGE);
    // Expand every row of the first page: pictures drawn.
    for (const tr of Array.from(document.querySelectorAll('#rows tr[data-row]'))) expanded.add(Number(tr.dataset.row));
    update();
    r.pictures = document.querySelectorAll('#rows tr.detail svg').length;
    r.details = document.querySelectorAll('#rows tr.detail').length;
    // What the table shows for each row, to be compared with the data by the test.
    r.table = Array.from(document.querySelectorAll('#rows tr[data-row]')).map((tr) => {
      const o = { row: Number(tr.dataset.row) };
      for (const td of tr.querySelectorAll('td[data-key]')) o[td.dataset.key] = td.dataset.value === undefined ? td.textContent : Number(td.dataset.value);
      return o;
    });
    r.links = Array.from(document.querySelectorAll('a.view')).map((a) => a.getAttribute('href'));
    r.scripts = document.scripts.length;
    r.injected = document.querySelectorAll('[onload],[onerror],[onclick]').length + (window.pwned ? 1 : 0);
    r.ok = errors.length === 0 && r.sorted_desc && r.sorted_asc && r.filter_ok;
    const out = el('pre', JSON.stringify(r));
    out.id = 'selftest';
    document.body.appendChild(out);
  }
})();
