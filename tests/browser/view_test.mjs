// Opens pages written by `cellc view` in headless Chromium and checks what they show.
// Run by tests/browser.rs: `node view_test.mjs PAGES.json`, where the file lists
// {"page": path, "screenshot": path or null, "animated": bool}; prints one JSON result
// per page on standard output and exits non-zero when any check fails.
import { chromium } from 'playwright-core';
import { readFileSync } from 'node:fs';
import { pathToFileURL } from 'node:url';

const pages = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const executablePath = process.env.CHROMIUM || '/usr/bin/chromium';
const browser = await chromium.launch({
  executablePath,
  headless: true,
  args: [
    '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync',
    '--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  ],
});

// In the page: pixels of the WebGL canvas differing from the background, around points.
async function pixels(page, points, radius) {
  return page.evaluate(([points, radius]) => {
    const gl = document.querySelector('#scene canvas');
    const c = document.createElement('canvas');
    c.width = gl.width; c.height = gl.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(gl, 0, 0);
    const rect = gl.getBoundingClientRect();
    const sx = gl.width / rect.width, sy = gl.height / rect.height;
    const bg = window.cellcView.background;
    const data = ctx.getImageData(0, 0, c.width, c.height).data;
    const at = (x, y) => { const i = 4 * (y * c.width + x); return [data[i], data[i + 1], data[i + 2]]; };
    const differs = (p) => Math.abs(p[0] - bg[0]) + Math.abs(p[1] - bg[1]) + Math.abs(p[2] - bg[2]) > 40;
    // The whole canvas on a grid: how much of it is not background.
    let drawn = 0, total = 0;
    for (let y = 0; y < c.height; y += 8) for (let x = 0; x < c.width; x += 8) { total++; if (differs(at(x, y))) drawn++; }
    const regions = points.map((p) => {
      if (!p) return null;
      const cx = Math.round((p.x - rect.left) * sx), cy = Math.round((p.y - rect.top) * sy);
      const out = [];
      let hit = 0;
      for (let dy = -radius; dy <= radius; dy++) for (let dx = -radius; dx <= radius; dx++) {
        const x = cx + dx, y = cy + dy;
        if (x < 0 || y < 0 || x >= c.width || y >= c.height) { out.push(null); continue; }
        const v = at(x, y);
        out.push(v);
        if (differs(v)) hit++;
      }
      return { hit, values: out };
    });
    return { drawn: drawn / total, regions };
  }, [points, radius]);
}

let failed = false;
for (const spec of pages) {
  const started = Date.now();
  const page = await browser.newPage({ viewport: { width: 1280, height: 760 } });
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('request', (r) => { if (!r.url().startsWith('file:') && !r.url().startsWith('data:')) errors.push('network request ' + r.url()); });
  const problems = [];
  await page.goto(pathToFileURL(spec.page).href);
  try {
    await page.waitForFunction(() => window.cellcView && window.cellcView.ready, null, { timeout: 60000 });
  } catch (e) {
    problems.push('the page never became ready');
  }
  const info = await page.evaluate(() => ({
    webgl: window.cellcView && window.cellcView.webgl,
    duration: window.cellcView ? window.cellcView.duration : 0,
    bodies: window.cellcView ? window.cellcView.bodies() : [],
  }));
  const result = { page: spec.page, duration: info.duration };
  if (!info.webgl) problems.push('no WebGL context');
  if (info.webgl && !spec.abstract) {
    const t0 = info.duration > 0 ? info.duration * 0.3 : 0;
    await page.evaluate((t) => window.cellcView.setTime(t), t0);
    // A robot link, a surface and an object where the page projects them.
    const pick = (kind) => info.bodies.find((b) => b.kind === kind && b.visible);
    const chosen = ['link', 'surface', 'object'].map((k) => (k === 'link' ? info.bodies.filter((b) => b.kind === 'link' && b.visible)[3] || pick(k) : pick(k)));
    const points = await page.evaluate((names) => names.map((n) => (n ? window.cellcView.project(n) : null)), chosen.map((b) => b && b.name));
    const seen = await pixels(page, points, 2);
    result.drawn = seen.drawn;
    if (seen.drawn < 0.02) problems.push('the scene is blank (' + (100 * seen.drawn).toFixed(1) + '% drawn)');
    ['link', 'surface', 'object'].forEach((k, i) => {
      if (!chosen[i]) { if (k !== 'object' || spec.object) problems.push('no visible ' + k); return; }
      const r = seen.regions[i];
      if (!r || r.hit === 0) problems.push(k + ' `' + chosen[i].name + '` is not drawn where it projects');
    });
    if (spec.screenshot) await page.screenshot({ path: spec.screenshot });
    if (spec.animated) {
      // The hand (or the last link) of an arm that moves: two times, two pictures.
      const names = info.bodies.filter((b) => b.kind === 'hand').map((b) => b.name);
      // Pairs of times tried in turn: an arm may stand still for a while (a grasp, the
      // other arm's turn).
      const pairs = [[0.25, 0.5], [0.1, 0.35], [0.5, 0.75], [0.05, 0.9]];
      // A pair counts when a hand moves on the screen and the pixels around it change:
      // a hand can move behind something (the Panda's behind its cage's cubes) and leave
      // the picture there the same, so the next pair is tried before the page is blamed.
      let moves = false, tried = [];
      result.changed_px = 0;
      for (const [f1, f2] of pairs) {
        const t1 = info.duration * f1, t2 = info.duration * f2;
        const moved = await page.evaluate(([names, t1, t2]) => {
          const v = window.cellcView;
          v.setTime(t1);
          const a = names.map((n) => v.project(n));
          v.setTime(t2);
          const b = names.map((n) => v.project(n));
          let best = -1, far = 0;
          a.forEach((p, i) => {
            if (!p || !b[i]) return;
            const d = Math.hypot(p.x - b[i].x, p.y - b[i].y);
            if (d > far) { far = d; best = i; }
          });
          return { best, far, a: a[best] || null, b: b[best] || null };
        }, [names, t1, t2]);
        result.moved_px = Math.max(result.moved_px || 0, moved.far);
        tried.push(t1.toFixed(2) + ' s and ' + t2.toFixed(2) + ' s');
        if (moved.best < 0 || moved.far < 3) continue;
        moves = true;
        await page.evaluate((t) => window.cellcView.setTime(t), t1);
        const first = await pixels(page, [moved.a, moved.b], 4);
        await page.evaluate((t) => window.cellcView.setTime(t), t2);
        const second = await pixels(page, [moved.a, moved.b], 4);
        let changed = 0;
        for (let r = 0; r < 2; r++) {
          first.regions[r].values.forEach((v, i) => {
            const w = second.regions[r].values[i];
            if (v && w && Math.abs(v[0] - w[0]) + Math.abs(v[1] - w[1]) + Math.abs(v[2] - w[2]) > 40) changed++;
          });
        }
        result.changed_px = Math.max(result.changed_px, changed);
        if (changed >= 4) break;
      }
      if (!moves) problems.push('no hand moves between ' + tried.join(', nor between '));
      else if (result.changed_px < 4) problems.push('the pictures do not differ where the arm is, at any of ' + tried.join('; '));
    }
    if (spec.object) {
      // Clicking a state shows a witness configuration: some state of the object has one.
      const shown = await page.evaluate((o) => {
        for (let n = 0; n < 200; n++) if (window.cellcView.selectState(o, n)) return n;
        return -1;
      }, spec.object);
      if (shown < 0) problems.push('no state of `' + spec.object + '` shows a witness configuration');
      else result.witness_state = shown;
    }
  } else if (spec.screenshot) {
    await page.screenshot({ path: spec.screenshot });
  }
  problems.push(...errors.map((e) => 'console error: ' + e));
  result.problems = problems;
  result.ms = Date.now() - started;
  if (problems.length) failed = true;
  console.log(JSON.stringify(result));
  await page.close();
}
await browser.close();
process.exit(failed ? 1 : 0);
