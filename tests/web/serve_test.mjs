// foton serve in a real browser: Debian's chromium, headless, driven by Playwright. The page
// lists the scenes, starts a small render, shows the preview updating pass by pass, saves an
// EXR equal bit for bit to the command line's render with the same seed and passes, shows a
// bad scene's file:line message, stops a long render, and the server opens nothing outside
// its scene folders.
//
// usage: node tests/web/serve_test.mjs FOTON_BINARY SOURCE_DIR
import { chromium } from 'playwright-core';
import { spawn, execFileSync } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';
import assert from 'node:assert/strict';

const [foton, source] = process.argv.slice(2);
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'foton-web-'));
const badDir = path.join(tmp, 'bad');
fs.mkdirSync(badDir);
fs.writeFileSync(path.join(badDir, 'broken.xml'),
                 '<scene>\n<film width="8" height="8"/>\n<camera type="spherical"/>\n</scene>\n');

// A scene whose mesh names a material library outside the served folders (defect 17: its
// first line once reached the error that /api/status publishes).
fs.writeFileSync(path.join(badDir, 'leak.obj'),
                 'mtllib /etc/passwd\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n');
fs.writeFileSync(path.join(badDir, 'leak.xml'),
                 '<scene>\n<film width="8" height="8"/>\n<camera type="perspective"><eye x="0" ' +
                 'y="0" z="5"/><target x="0" y="0" z="0"/></camera>\n<lights><point>' +
                 '<position x="0" y="0" z="5"/></point></lights>\n<objects><triangle_mesh ' +
                 'src="leak.obj"/></objects>\n</scene>\n');

const shared = path.join(source, '..', 'shared');
const server = spawn(foton, ['serve', '--port', '0', '--scenes', path.join(source, 'scenes'),
                             '--scenes', badDir, '--allow-read', shared],
                     {stdio: ['ignore', 'pipe', 'inherit']});
const url = await new Promise((resolve, reject) => {
  let out = '';
  server.stdout.on('data', (d) => {
    out += d;
    const m = out.match(/http:\/\/[0-9.]+:\d+\//);
    if (m) resolve(m[0]);
  });
  server.on('exit', (code) => reject(new Error(`foton serve exited with ${code}`)));
  setTimeout(() => reject(new Error('foton serve did not start')), 10000);
});

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--no-sandbox'],
});
let failed = false;
try {
  const page = await browser.newPage({acceptDownloads: true});
  const previews = [];
  page.on('request', (r) => { if (r.url().includes('/api/pixels')) previews.push(r.url()); });
  await page.goto(url);
  await page.waitForSelector('#scene option[value="scenes/cornell-diffuse.xml"]', {state: 'attached'});
  // Subfolders and pbrt-v4 scenes are listed too (app/scene_list.h).
  await page.waitForSelector('#scene option[value="scenes/pbrt/cornell/path_diffuse.pbrt"]',
                             {state: 'attached'});

  // A progressive render for a second and a half: the preview follows the passes.
  await page.selectOption('#scene', 'scenes/cornell-diffuse.xml');
  await page.selectOption('#integrator', 'path');
  for (const [id, v] of [['#width', '48'], ['#height', '32'], ['#spp', '1'], ['#passes', '0'],
                         ['#time', '1.5'], ['#seed', '5'], ['#threads', '2']])
    await page.fill(id, v);
  await page.click('#start');
  await page.waitForSelector('#state[data-state="running"]');
  await page.waitForSelector('#state[data-state="done"]', {timeout: 30000});
  const passes = Number(await page.getAttribute('#state', 'data-passes'));
  assert.ok(passes >= 2, `passes ${passes}`);
  await page.waitForFunction(() => document.getElementById('canvas').dataset.width === '48');
  assert.ok(previews.length >= 2, `the preview was fetched ${previews.length} times`);

  // Saved EXR = the command line's with the same seed and passes, bit for bit.
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#save-exr')]);
  const served = path.join(tmp, 'served.exr');
  await download.saveAs(served);
  const cli = path.join(tmp, 'cli.exr');
  execFileSync(foton, ['render', path.join(source, 'scenes/cornell-diffuse.xml'), '--integrator',
                       'path', '--width', '48', '--height', '32', '--spp', '1', '--passes',
                       String(passes), '--seed', '5', '--threads', '2', '-q', '-o', cli]);
  const compare = execFileSync(foton, ['compare', served, cli]).toString();
  assert.match(compare, /max_abs 0\n/, compare);

  // The viewer: AOV layers, zoom (about the viewport's centre: the pixels read are near it), the pixel under the cursor equal to the saved EXR's, the
  // reference as B of an A/B view, the error curve of every pass.
  await page.fill('#time', '0');
  await page.fill('#passes', '3');
  for (const [id, v] of [['#width', '64'], ['#height', '64'], ['#aov', 'albedo,depth']])
    await page.fill(id, v);
  const refName = 'shared/refs/cornell_diffuse_path_512spp.exr';
  await page.selectOption('#reference', refName);
  await page.click('#start');
  await page.waitForSelector('#state[data-state="done"]', {timeout: 30000});
  await page.waitForSelector('#layer option[value="albedo"]', {state: 'attached'});
  await page.waitForFunction(() => document.getElementById('canvas').dataset.width === '64');
  const curve = await page.getAttribute('#curve-line', 'points');
  assert.equal(curve.trim().split(' ').length, 3, curve);
  const box = await page.locator('#viewport').boundingBox();
  const scaleBefore = Number(await page.getAttribute('#canvas', 'data-scale'));
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  for (let i = 0; i < 4; ++i) await page.mouse.wheel(0, -100);
  // Chromium may split a wheel turn into several events: wait until the zoom settles.
  let settled = scaleBefore;
  for (let same = 0; same < 3;) {
    await page.waitForTimeout(150);
    const now = Number(await page.getAttribute('#canvas', 'data-scale'));
    same = now === settled ? same + 1 : 0;
    settled = now;
  }
  assert.ok(settled > scaleBefore, `zoom ${scaleBefore} -> ${settled}`);
  await page.evaluate(() => window.scrollTo(0, 0));
  // A pixel a little off the middle of what the viewport shows.
  const [px, py] = await page.evaluate(() => {
    const c = document.getElementById('canvas'), v = document.getElementById('viewport');
    const s = Number(c.dataset.scale);
    return [Math.floor((v.clientWidth / 2 - Number(c.dataset.ox)) / s) + 3,
            Math.floor((v.clientHeight / 2 - Number(c.dataset.oy)) / s) - 2];
  });
  assert.ok(px >= 0 && px < 64 && py >= 0 && py < 64, `${px}, ${py}`);
  const hover = async (x, y) => {
    const c = await page.evaluate(() => {
      const r = document.getElementById('viewport').getBoundingClientRect();
      return {...document.getElementById('canvas').dataset, left: r.left, top: r.top};
    });
    const scale = Number(c.scale);
    await page.mouse.move(c.left + Number(c.ox) + (x + 0.5) * scale,
                          c.top + Number(c.oy) + (y + 0.5) * scale);
    const p = await page.evaluate(() => ({...document.getElementById('pixel').dataset}));
    assert.equal(Number(p.x), x, JSON.stringify({c, p}));
    assert.equal(Number(p.y), y);
    return JSON.parse(p.values);
  };
  const [saved] = await Promise.all([page.waitForEvent('download'), page.click('#save-exr')]);
  const viewed = path.join(tmp, 'viewed.exr');
  await saved.saveAs(viewed);
  // The EXR's pixels through the Python module (when it was built), exactly as stored.
  const moduleDir = path.join(path.dirname(foton), 'python');
  const exrPixel = (file, channels, x, y, box) => JSON.parse(execFileSync('/usr/bin/python3', [
    '-c', 'import foton, json, sys; a = foton.read_exr(sys.argv[1], sys.argv[2].split(",") ' +
          'if sys.argv[2] else None); b = int(sys.argv[5]); h, w = a.shape[:2]; ' +
          'a = a.reshape(h // b, b, w // b, b, -1).mean(axis=(1, 3), dtype="float64"); ' +
          'print(json.dumps([float(v) for v in a[int(sys.argv[4]), int(sys.argv[3])].ravel()]))',
    file, channels, String(x), String(y), String(box)], {env: {...process.env, PYTHONPATH: moduleDir}}));
  const hasModule = fs.existsSync(moduleDir);
  const pixel = await hover(px, py);
  if (hasModule) assert.deepEqual(pixel, exrPixel(viewed, '', px, py, 1));
  await page.selectOption('#layer', 'albedo');
  await page.waitForFunction(() => document.getElementById('pixel') && true);
  await page.waitForTimeout(300);
  const albedo = await hover(px, py);
  if (hasModule) assert.deepEqual(albedo, exrPixel(viewed, 'Albedo.R,Albedo.G,Albedo.B', px, py, 1));
  await page.selectOption('#layer', 'image');
  await page.waitForTimeout(300);
  await page.click('#ab');
  assert.equal(await page.inputValue('#mode'), 'reference');
  const b = await hover(px, py);
  if (hasModule) {
    const expected = exrPixel(path.join(shared, 'refs/cornell_diffuse_path_512spp.exr'), '', px, py, 8);
    for (let c = 0; c < 3; ++c) assert.ok(Math.abs(b[c] - expected[c]) <= 1e-5 * (1 + expected[c]),
                                          `${b} vs ${expected}`);
  } else {
    console.log('web page: the Python module is not built; pixel values not checked against the EXR');
  }
  assert.notDeepEqual(b, pixel);
  await page.click('#ab');
  assert.deepEqual(await hover(px, py), pixel);
  await page.fill('#aov', '');
  await page.fill('#passes', '0');
  await page.selectOption('#reference', '');

  // A bad scene: the loader's file:line message on the page.
  await page.selectOption('#scene', 'bad/broken.xml');
  await page.click('#start');
  await page.waitForSelector('#state[data-state="error"]');
  const error = await page.textContent('#error');
  assert.match(error, /broken\.xml:3: .*spherical/, error);
  // A file outside the served folders is refused unread: nothing of it in the message.
  await page.selectOption('#scene', 'bad/leak.xml');
  await page.click('#start');
  // The text is read in the same check that finds it (the page may redraw the box between two
  // separate reads).
  const leak = await (await page.waitForFunction(() => {
    const t = document.querySelector('#error').textContent;
    return t.includes('leak') ? t : null;
  })).jsonValue();
  assert.match(leak, /outside the folders this server reads/, leak);
  assert.doesNotMatch(leak, /root:/, leak);

  // Stop: a long render ends after the pass in flight.
  await page.selectOption('#scene', 'scenes/cornell-diffuse.xml');
  await page.fill('#time', '60');
  await page.click('#start');
  await page.waitForSelector('#state[data-state="running"]');
  await page.click('#stop');
  await page.waitForSelector('#state[data-state="stopped"]', {timeout: 10000});

  // Stop inside a pass: a photon pre-pass of 400 M photons (minutes of tracing) ends within
  // a chunk of /api/stop, not after the pass (defect 12). The bound is loose on purpose: the
  // pass checks the flag every 4,096 photons and the stages after it are skipped; without the
  // checks this took minutes (measured here: 0.08-0.15 s).
  const stopSeconds = await page.evaluate(async () => {
    const h = {'X-Foton-Request': '1'};
    const status = async () => (await (await fetch('/api/status')).json()).state;
    const body = new URLSearchParams({scene: 'scenes/cornell-caustics.xml', integrator: 'photon',
                                      width: '32', height: '32', set: 'global_photons=400000000'});
    const r = await fetch('/api/render', {method: 'POST', body, headers: h});
    if (r.status !== 200) return -r.status;
    while (await status() !== 'running') await new Promise((f) => setTimeout(f, 20));
    await new Promise((f) => setTimeout(f, 300));  // well inside the photon pass
    const t0 = performance.now();
    await fetch('/api/stop', {method: 'POST', headers: h});
    while (await status() === 'running') await new Promise((f) => setTimeout(f, 20));
    return (performance.now() - t0) / 1000;
  });
  // 5 s: far below the minutes it took without the checks, and above what a machine busy
  // with a parallel build makes of 0.1 s (1.3 s was seen).
  assert.ok(stopSeconds >= 0 && stopSeconds < 5, `stop took ${stopSeconds} s`);
  console.log(`web page: a 400 M photon pass stopped ${stopSeconds.toFixed(3)} s after /api/stop`);

  // Nothing outside the scene folders: names not listed are refused, paths are not files.
  const refused = await page.evaluate(async () => {
    const body = new URLSearchParams({scene: '../../../etc/passwd'});
    const r = await fetch('/api/render', {method: 'POST', body, headers: {'X-Foton-Request': '1'}});
    return [r.status, (await r.json()).error];
  });
  assert.equal(refused[0], 400);
  assert.match(refused[1], /unknown scene/);

  // Other sites cannot drive it (request_guard.h): the page's own POST without its token, a
  // cross-origin POST from another page (a form needs no preflight), and this server reached
  // under another host name (DNS rebinding) are refused with 403.
  const untokened = await page.evaluate(async () => (await fetch('/api/stop', {method: 'POST'})).status);
  assert.equal(untokened, 403);
  const other = await browser.newPage();
  await other.goto('about:blank');
  const crossSite = await other.evaluate(async (target) => {
    try {
      const r = await fetch(target + 'api/render', {
        method: 'POST', mode: 'no-cors',
        body: new URLSearchParams({scene: 'scenes/cornell-diffuse.xml', time: '60'})});
      return r.type;  // opaque: sent, and the server's guard answers 403 unseen
    } catch (e) { return 'blocked'; }
  }, url);
  assert.ok(['opaque', 'blocked'].includes(crossSite), crossSite);
  // ... and started nothing: the last render is still the stopped one.
  const state = await page.evaluate(async () => (await (await fetch('/api/status')).json()).state);
  assert.equal(state, 'stopped');
  const raw = (method, pathName, headers, body) => new Promise((resolve, reject) => {
    const u = new URL(url);
    // A new connection each time (agent: false): a pooled keep-alive one already has its
    // server worker, which would hide a server that cannot take new connections.
    const req = http.request({host: u.hostname, port: u.port, method, path: pathName, headers,
                              agent: false},
                             (res) => { res.resume(); resolve(res.statusCode); });
    req.on('error', (e) => (e.code === 'EPIPE' || e.code === 'ECONNRESET' ? resolve(413)
                                                                           : reject(e)));
    if (body) req.write(body);
    req.end();
  });
  assert.equal(await raw('POST', '/api/render', {'Origin': 'https://evil.example',
                                                 'X-Foton-Request': '1'}), 403);
  assert.equal(await raw('POST', '/api/stop', {'Sec-Fetch-Site': 'cross-site'}), 403);
  assert.equal(await raw('GET', '/api/status', {'Host': 'evil.example:' + new URL(url).port}),
               403);
  assert.equal(await raw('GET', '/api/status', {}), 200);

  // The command line's limits, before anything starts: each a 4xx, and the server answers on.
  const form = {'X-Foton-Request': '1', 'Content-Type': 'application/x-www-form-urlencoded'};
  for (const q of ['width=32768&height=32768', 'time=nan', 'time=inf', 'spp=1e12',
                   'spp=1000000000000', 'width=4294967297', 'threads=100000']) {
    const status = await raw('POST', '/api/render', form,
                             'scene=scenes%2Fcornell-diffuse.xml&' + q);
    assert.equal(status, 400, q);
  }
  assert.ok((await raw('POST', '/api/render', form, 'x'.repeat(64 << 20))) >= 400);
  assert.equal(await raw('GET', '/api/status', {}), 200);
  const after = await page.evaluate(async () => (await (await fetch('/api/status')).json()).state);
  assert.equal(after, 'stopped');
  const traversal = await page.evaluate(async () => (await fetch('/../../etc/passwd')).status);
  assert.equal(traversal, 404);

  // 20 idle and half-open connections (defect 23: they once held all 8 workers for their 5 s
  // read timeout, 18.5 s of delay) must not keep the page's request waiting.
  const port = Number(new URL(url).port);
  const idle = [];
  for (let i = 0; i < 20; ++i) {
    const sock = net.connect(port, '127.0.0.1');
    if (i % 2) sock.on('connect', () => sock.write('GET /api/status HTTP/1.1\r\nHost: x'));
    sock.on('error', () => {});
    idle.push(sock);
  }
  await new Promise((f) => setTimeout(f, 200));
  // On a new connection (raw's agent: false; the page's own keep-alive one has its worker).
  const answered = await Promise.race([
    raw('GET', '/api/status', {'Connection': 'close'}),
    new Promise((f) => setTimeout(() => f('no answer within 3 s'), 3000)),
  ]);
  assert.equal(answered, 200);
  for (const sock of idle) sock.destroy();

  // 50 image requests at once (defect 13: each copied the whole film): all served, the same.
  const images = await page.evaluate(async () => {
    const all = await Promise.all(Array.from({length: 50}, () => fetch('/api/image.png')));
    const bodies = await Promise.all(all.map((r) => r.arrayBuffer()));
    const sizes = new Set(bodies.map((b) => b.byteLength));
    return [all.every((r) => r.status === 200), sizes.size, bodies[0].byteLength];
  });
  assert.deepEqual(images.slice(0, 2), [true, 1]);
  assert.ok(images[2] > 0);
  console.log(`web page: ${passes} passes previewed in ${previews.length} fetches; saved EXR ` +
              'equals the CLI render; bad scene, stop, path and cross-site checks pass');
} catch (e) {
  console.error(e);
  failed = true;
} finally {
  await browser.close();
  server.kill();
  fs.rmSync(tmp, {recursive: true, force: true});
}
process.exit(failed ? 1 : 0);
