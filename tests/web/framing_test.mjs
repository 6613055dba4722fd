// The viewer frames every view: drives the page at GET / in headless Chromium and measures,
// from the canvas's pixels, where the object is drawn. Usage:
//   node framing_test.mjs URL ELONGATED.glb ROUND.glb
// For each mesh and each view (input, sphere, remesh, morph) the bounding box of the pixels
// that are not the background must be whole (no object pixel on the border rows or columns)
// and its larger extent, as a share of the canvas in its own direction, between 30% and 90%.
// Not both extents: an elongated object seen side-on is short across, at any margin. Views
// of a round object (the unit sphere's every view, and every mesh's sphere view) must fill
// 30-90% in both directions. The morph view fits its mesh and its sphere together, so at
// the slider's sphere end it must stay whole but may fill less (15%). Measured at two canvas
// shapes (a tall one beside the panels, a wide one in the narrow layout) to check the fit
// follows the aspect ratio and a resize.
// Also: the empty canvas shows a hint; the mesh/sphere slider shows in Morph only; the heat
// map changes the input and sphere views and is disabled (with a reason) in Remesh; the
// "Try an example" button maps examples/spot.glb and shows its sphere. With SCREENSHOTS=DIR,
// the example's views are saved as DIR/page-{input,sphere,remesh,morph}.png.
import { launchBrowser, openPage } from './browser.mjs';

const [url, elongated, round] = process.argv.slice(2);
let failures = 0;
const fail = (message) => { console.error(`FAIL: ${message}`); ++failures; };
const VIEWS = ['input', 'sphere', 'remesh', 'morph'];
const WIDE = { width: 1280, height: 900 };  // three columns: the canvas is taller than wide
const NARROW = { width: 900, height: 900 };  // one column: the canvas is wider than tall

// The canvas's object pixels: those away from the background colour (#20242b).
function measure() {
  const source = document.querySelector('canvas');
  const { width: w, height: h } = source;
  const copy = Object.assign(document.createElement('canvas'), { width: w, height: h });
  const context = copy.getContext('2d');
  context.drawImage(source, 0, 0);
  const d = context.getImageData(0, 0, w, h).data;
  let minX = w, minY = h, maxX = -1, maxY = -1, count = 0, hash = 0;
  for (let y = 0; y < h; ++y) {
    for (let x = 0; x < w; ++x) {
      const i = 4 * (y * w + x);
      hash = (Math.imul(hash, 31) + (d[i] << 16 | d[i + 1] << 8 | d[i + 2])) | 0;
      if (Math.abs(d[i] - 0x20) + Math.abs(d[i + 1] - 0x24) + Math.abs(d[i + 2] - 0x2b) <= 24) continue;
      ++count;
      if (x < minX) minX = x;
      if (x > maxX) maxX = x;
      if (y < minY) minY = y;
      if (y > maxY) maxY = y;
    }
  }
  return { w, h, minX, minY, maxX, maxY, count, hash };
}

// Two animation frames: what the last change asked for is on the canvas.
const settle = (page) => page.evaluate(() => new Promise((done) =>
  requestAnimationFrame(() => requestAnimationFrame(done))));

// Checks the canvas as drawn now; returns its measure.
async function checkFraming(page, label, isRound, least = 0.3) {
  await settle(page);
  const m = await page.evaluate(measure);
  if (!m.count) {
    fail(`${label}: nothing drawn`);
    return m;
  }
  const fx = (m.maxX - m.minX + 1) / m.w, fy = (m.maxY - m.minY + 1) / m.h;
  const summary = `${label}: canvas ${m.w}x${m.h}, object x ${m.minX}-${m.maxX} (${(100 * fx).toFixed(0)}%), ` +
    `y ${m.minY}-${m.maxY} (${(100 * fy).toFixed(0)}%)`;
  console.log(summary);
  if (m.minX === 0 || m.minY === 0 || m.maxX === m.w - 1 || m.maxY === m.h - 1)
    fail(`${summary}: the object touches the canvas's border (clipped)`);
  const larger = Math.max(fx, fy);
  if (larger < least || larger > 0.9)
    fail(`${summary}: its larger extent is not within ${100 * least}-90%`);
  if (isRound && (Math.min(fx, fy) < 0.3 || Math.min(fx, fy) > 0.9))
    fail(`${summary}: a round object should fill 30-90% both ways`);
  return m;
}

async function mapFile(page, file) {
  await page.locator('input[type="file"]').setInputFiles(file);
  await waitForJob(page, file);
}

async function waitForJob(page, what) {
  await page.waitForFunction(
    () => !['idle', 'submitting', 'queued', 'running'].includes(document.body.dataset.status),
    null, { timeout: 120000 });
  const status = await page.evaluate(() => document.body.dataset.status);
  if (status !== 'succeeded') throw new Error(`${what}: job ended ${status}`);
}

async function show(page, view) {
  await page.locator(`#views [data-view="${view}"]`).click();
  await settle(page);
}

const selectedView = (page) =>
  page.evaluate(() => document.querySelector('#views [aria-selected="true"]')?.dataset.view);

const browser = await launchBrowser();
try {
  const page = await openPage(browser, WIDE);
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(url);

  // Before any upload: a hint with the example button, and no slider.
  if (!await page.locator('#hint').isVisible()) fail('no hint on the empty canvas');
  if (!await page.locator('#hint button.example').isVisible()) fail('the hint has no example button');
  if (await page.locator('#morph-control').isVisible()) fail('the morph slider shows before any job');

  for (const [file, isRound] of [[elongated, false], [round, true]]) {
    const name = file.split('/').pop();
    await page.setViewportSize(WIDE);
    await page.locator('#quality').selectOption('fast');  // the views are what is tested
    await mapFile(page, file);
    if (await page.locator('#hint').isVisible()) fail(`${name}: the hint still shows`);
    if (await selectedView(page) !== 'sphere') fail(`${name}: the sphere view is not shown when the job ends`);
    for (const view of VIEWS) {
      await show(page, view);
      const plain = await checkFraming(page, `${name} ${view}`, isRound || view === 'sphere');
      const slider = await page.locator('#morph-control').isVisible();
      if (slider !== (view === 'morph')) fail(`${name} ${view}: the slider ${slider ? 'shows' : 'is hidden'}`);
      const heat = page.locator('#heat');
      if (view === 'remesh') {
        if (!await heat.isDisabled()) fail(`${name} remesh: the heat map checkbox is enabled`);
        const reason = await page.locator('#heat-toggle').getAttribute('title');
        if (!reason?.includes('remesh')) fail(`${name} remesh: no reason for the disabled heat map: ${reason}`);
        continue;
      }
      if (await heat.isDisabled()) { fail(`${name} ${view}: the heat map checkbox is disabled`); continue; }
      await heat.check();
      const heated = await checkFraming(page, `${name} ${view} + heat`, isRound || view === 'sphere');
      if (heated.hash === plain.hash) fail(`${name} ${view}: the heat map changes nothing`);
      if (!await page.locator('#heat-legend').isVisible()) fail(`${name} ${view}: no heat map legend`);
      await heat.uncheck();
    }
    // The morph fits mesh and sphere at once: the slider's sphere end stays whole too (and
    // smaller than the elongated mesh: a sphere of the mesh's area).
    await page.locator('#morph').fill('1');
    await checkFraming(page, `${name} morph at the sphere`, isRound, 0.15);
    await page.locator('#morph').fill('0');
    // A wide canvas (the narrow layout): the views frame again for its aspect ratio.
    await page.setViewportSize(NARROW);
    await checkFraming(page, `${name} morph, wide canvas`, isRound);
    for (const view of ['input', 'sphere']) {
      await show(page, view);
      await checkFraming(page, `${name} ${view}, wide canvas`, isRound || view === 'sphere');
    }
  }

  // "Try an example": a fresh page, one click, the job succeeds and the sphere shows.
  await page.setViewportSize(WIDE);
  await page.goto(url);
  const start = Date.now();
  await page.locator('#example').click();
  await waitForJob(page, 'the example');
  console.log(`example: succeeded after ${((Date.now() - start) / 1000).toFixed(1)} s`);
  const chosen = await page.evaluate(() => [...document.querySelector('#file').files].map((f) => f.name));
  if (chosen.join() !== 'spot.glb') fail(`the example is not the chosen file: ${chosen}`);
  if (await selectedView(page) !== 'sphere') fail('the example: the sphere view is not shown');
  await checkFraming(page, 'example sphere', true);
  for (const view of VIEWS) {
    await show(page, view);
    if (view !== 'sphere') await checkFraming(page, `example ${view}`, false);
    if (process.env.SCREENSHOTS) {
      if (view === 'morph') await page.locator('#morph').fill('0.5');  // halfway to the sphere
      await page.waitForTimeout(200);
      await page.screenshot({ path: `${process.env.SCREENSHOTS}/page-${view}.png` });
    }
  }
  if (errors.length) fail(`console errors:\n  ${errors.join('\n  ')}`);
} catch (error) {
  fail(error.message);
} finally {
  await browser.close();
}
if (failures) process.exitCode = 1;
else console.log('framing: ok');
