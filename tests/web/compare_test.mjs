// A wrapped job on the page (preparation "wrap"): the "Original | envelope" view draws the
// asset as uploaded on the left half of the canvas and the envelope, coloured by its
// distance to the original, on the right, and its legend states the largest distance as
// metrics.json does (morph.vertex_distances.max). MESH (a GLB), then a torus generated as
// binary STL (read by three.js's loader too) and as OFF (no reader in the browser: the
// left half says so). Usage: node compare_test.mjs URL MESH.
import { launchBrowser, openPage } from './browser.mjs';

const [url, mesh] = process.argv.slice(2);
const fail = (message) => { console.error(`FAIL: ${message}`); process.exitCode = 1; };

const browser = await launchBrowser();
// A torus (genus 1: wrapped) written as binary STL or OFF, for the other readers.
function torusFile(type) {
  const n = 24, m = 12, v = [], f = [];
  for (let i = 0; i < n; ++i)
    for (let j = 0; j < m; ++j) {
      const a = 2 * Math.PI * i / n, b = 2 * Math.PI * j / m;
      v.push([(2 + 0.7 * Math.cos(b)) * Math.cos(a), (2 + 0.7 * Math.cos(b)) * Math.sin(a), 0.7 * Math.sin(b)]);
    }
  const at = (i, j) => (i % n) * m + (j % m);
  for (let i = 0; i < n; ++i)
    for (let j = 0; j < m; ++j)
      f.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)], [at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
  if (type === 'off')
    return Buffer.from(`OFF\n${v.length} ${f.length} 0\n` + v.map((p) => `${p.join(' ')}\n`).join('') + f.map((t) => `3 ${t.join(' ')}\n`).join(''));
  const stl = Buffer.alloc(84 + 50 * f.length);
  stl.writeUInt32LE(f.length, 80);
  f.forEach((t, k) => t.forEach((index, c) => v[index].forEach((x, d) => stl.writeFloatLE(x, 84 + 50 * k + 12 + 12 * c + 4 * d))));
  return stl;
}

// Maps `file` with preparation "wrap" and checks the side-by-side view: `models` drawn
// (2, or 1 with a note when the browser cannot read the format).
async function check(file, models) {
  const page = await openPage(browser, { width: 1280, height: 900 });
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(e.message));
  const name = file.name ?? file.split('/').pop();
  const failHere = (message) => fail(`${name}: ${message}`);

  await page.goto(url);
  await page.selectOption('#prepare', 'wrap');
  await page.selectOption('#quality', 'fast');
  await page.locator('input[type="file"]').setInputFiles([file]);
  await page.waitForFunction(
    () => !['idle', 'submitting', 'queued', 'running'].includes(document.body.dataset.status),
    null, { timeout: 120000 });
  const status = await page.evaluate(() => document.body.dataset.status);
  if (status !== 'succeeded') throw new Error(`${name}: job ended ${status}: ${await page.locator('#error').textContent()}`);

  // The metrics table says the envelope is what preparation did (not "none needed").
  const preparation = await page.locator('#metrics tr', { hasText: 'preparation (wrap)' }).textContent();
  if (!/replaced by an envelope of [\d,]+ faces/.test(preparation)) failHere(`the preparation row reads: ${preparation}`);

  const button = page.locator('#views [data-view="compare"]');
  if (await button.isHidden() || await button.isDisabled()) throw new Error(`${name}: no "Original | envelope" view`);
  await button.click();
  await page.waitForTimeout(800);
  const drawn = await page.evaluate(() => document.getElementById('canvas-box').dataset.compareModels);
  if (drawn !== String(models)) failHere(`the side-by-side view has ${drawn} models, not ${models}`);
  if (await page.locator('#compare-labels').isHidden()) failHere('the side-by-side labels are hidden');
  const note = await page.locator('#compare-note');
  if (models === 1 && (await note.isHidden() || !(await note.textContent()).includes('no reader')))
    failHere('no note says why the original is not shown');
  if (models === 2 && !(await note.isHidden())) failHere(`a note: ${await note.textContent()}`);

  // Each half drawn (pixels off the background #20242b); the heat map's blue on the right
  // half only (the original is plain grey).
  const halves = await page.evaluate(() => {
    const source = document.querySelector('canvas');
    const copy = Object.assign(document.createElement('canvas'), { width: 320, height: 120 });
    const context = copy.getContext('2d');
    context.drawImage(source, 0, 0, 320, 120);
    return [0, 160].map((x0) => {
      const d = context.getImageData(x0, 0, 160, 120).data;
      const seen = new Set();
      let blue = 0, drawn = 0;
      for (let i = 0; i < d.length; i += 4) {
        drawn += Math.abs(d[i] - 0x20) + Math.abs(d[i + 1] - 0x24) + Math.abs(d[i + 2] - 0x2b) > 30;
        seen.add((d[i] >> 3) << 10 | (d[i + 1] >> 3) << 5 | d[i + 2] >> 3);
        blue += d[i + 2] > d[i] + 50;
      }
      return { colours: seen.size, blue, drawn };
    });
  });
  console.log(`${name} side by side: original ${JSON.stringify(halves[0])}, envelope ${JSON.stringify(halves[1])}`);
  if (models === 2 && halves[0].drawn < 500) failHere('the original\'s half looks blank');
  if (models === 1 && halves[0].drawn > 0) failHere('the original\'s half is drawn though not read');
  if (halves[1].drawn < 500 || halves[1].colours < 20) failHere('the envelope\'s half looks blank');
  if (halves[1].blue < 200 || halves[0].blue > halves[1].blue / 10)
    failHere('the envelope is not coloured by distance (or the original is)');

  // The legend's max is the morph's _DISTANCE max, as metrics.json states it.
  if (await page.locator('#distance-legend').isHidden()) failHere('no distance legend');
  const shown = await page.evaluate(() => ({
    max: Number(document.getElementById('distance-legend').dataset.max),
    text: document.getElementById('distance-max').textContent,
  }));
  const href = await page.locator('#downloads a', { hasText: 'metrics.json' }).getAttribute('href');
  const metrics = await (await page.request.get(new URL(href, url).href)).json();
  const expected = metrics.morph?.vertex_distances?.max;
  console.log(`${name} legend max ${shown.text} (${shown.max}); metrics.json ${expected}`);
  if (typeof expected !== 'number' || !(expected > 0)) failHere('metrics.json has no morph.vertex_distances.max');
  else if (Math.abs(shown.max - expected) > 1e-6 + 1e-5 * expected) failHere(`legend max ${shown.max} != ${expected}`);
  if (shown.text !== `${(100 * expected).toFixed(2)}%`) failHere(`legend reads ${shown.text}`);

  // Another view: the halves and the legend go.
  await page.locator('#views [data-view="sphere"]').click();
  await page.waitForTimeout(300);
  if (!(await page.locator('#distance-legend').isHidden())) failHere('the distance legend stays on the sphere view');
  if (!(await page.locator('#compare-labels').isHidden())) failHere('the side-by-side labels stay on the sphere view');
  if (process.env.SCREENSHOT && models === 2 && typeof file === 'string') {
    await button.click();
    await page.waitForTimeout(500);
    await page.screenshot({ path: process.env.SCREENSHOT });
  }
  if (errors.length) failHere(`console errors:\n  ${errors.join('\n  ')}`);
  await page.close();
}

try {
  await check(mesh, 2);
  // Binary STL (the slicer's format) through three.js's STL loader, and OFF (no reader in
  // the browser: the note). OBJ and PLY go through the same code as STL; each check is a wrapped
  // job in a software-rendered page, so CI's time keeps it to these.
  for (const [type, models] of [['stl', 2], ['off', 1]])
    await check({ name: `torus.${type}`, mimeType: 'application/octet-stream', buffer: torusFile(type) }, models);
} catch (error) {
  fail(error.message);
} finally {
  await browser.close();
}
