// A wrapped job on the page (preparation "wrap"): the "Original | envelope" view draws the
// asset as uploaded on the left half of the canvas and the envelope, coloured by its
// distance to the original, on the right, and its legend states the largest distance as
// metrics.json does (morph.vertex_distances.max). Usage: node compare_test.mjs URL MESH.
import { chromium } from 'playwright-core';

const [url, mesh] = process.argv.slice(2);
const fail = (message) => { console.error(`FAIL: ${message}`); process.exitCode = 1; };

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    '--disable-quic', '--no-first-run', '--disable-background-networking',
    '--disable-component-update', '--disable-sync'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(e.message));

  await page.goto(url);
  await page.selectOption('#prepare', 'wrap');
  await page.locator('input[type="file"]').setInputFiles([mesh]);
  await page.waitForFunction(
    () => !['idle', 'submitting', 'queued', 'running'].includes(document.body.dataset.status),
    null, { timeout: 120000 });
  const status = await page.evaluate(() => document.body.dataset.status);
  if (status !== 'succeeded') throw new Error(`job ended ${status}: ${await page.locator('#error').textContent()}`);

  const button = page.locator('#views [data-view="compare"]');
  if (await button.isHidden() || await button.isDisabled()) throw new Error('no "Original | envelope" view');
  await button.click();
  await page.waitForTimeout(800);
  const models = await page.evaluate(() => document.getElementById('canvas-box').dataset.compareModels);
  if (models !== '2') fail(`the side-by-side view has ${models} models, not the original and the envelope`);
  if (await page.locator('#compare-labels').isHidden()) fail('the side-by-side labels are hidden');

  // Each half drawn (many colours); the heat map's blue on the right half only (the
  // original is plain grey).
  const halves = await page.evaluate(() => {
    const source = document.querySelector('canvas');
    const copy = Object.assign(document.createElement('canvas'), { width: 320, height: 120 });
    const context = copy.getContext('2d');
    context.drawImage(source, 0, 0, 320, 120);
    return [0, 160].map((x0) => {
      const d = context.getImageData(x0, 0, 160, 120).data;
      const seen = new Set();
      let blue = 0;
      for (let i = 0; i < d.length; i += 4) {
        seen.add((d[i] >> 3) << 10 | (d[i + 1] >> 3) << 5 | d[i + 2] >> 3);
        blue += d[i + 2] > d[i] + 50;
      }
      return { colours: seen.size, blue };
    });
  });
  console.log(`side by side: original ${JSON.stringify(halves[0])}, envelope ${JSON.stringify(halves[1])}`);
  if (halves[0].colours < 20) fail('the original\'s half looks blank');
  if (halves[1].colours < 20) fail('the envelope\'s half looks blank');
  if (halves[1].blue < 200 || halves[0].blue > halves[1].blue / 10)
    fail('the envelope is not coloured by distance (or the original is)');

  // The legend's max is the morph's _DISTANCE max, as metrics.json states it.
  if (await page.locator('#distance-legend').isHidden()) fail('no distance legend');
  const shown = await page.evaluate(() => ({
    max: Number(document.getElementById('distance-legend').dataset.max),
    text: document.getElementById('distance-max').textContent,
  }));
  const href = await page.locator('#downloads a', { hasText: 'metrics.json' }).getAttribute('href');
  const metrics = await (await page.request.get(new URL(href, url).href)).json();
  const expected = metrics.morph?.vertex_distances?.max;
  console.log(`legend max ${shown.text} (${shown.max}); metrics.json ${expected}`);
  if (typeof expected !== 'number' || !(expected > 0)) fail('metrics.json has no morph.vertex_distances.max');
  else if (Math.abs(shown.max - expected) > 1e-6 + 1e-5 * expected) fail(`legend max ${shown.max} != ${expected}`);
  if (shown.text !== `${(100 * expected).toFixed(2)}%`) fail(`legend reads ${shown.text}`);

  // Another view: the halves and the legend go.
  await page.locator('#views [data-view="sphere"]').click();
  await page.waitForTimeout(300);
  if (!(await page.locator('#distance-legend').isHidden())) fail('the distance legend stays on the sphere view');
  if (!(await page.locator('#compare-labels').isHidden())) fail('the side-by-side labels stay on the sphere view');
  if (process.env.SCREENSHOT) {
    await button.click();
    await page.waitForTimeout(500);
    await page.screenshot({ path: process.env.SCREENSHOT });
  }
  if (errors.length) fail(`console errors:\n  ${errors.join('\n  ')}`);
} catch (error) {
  fail(error.message);
} finally {
  await browser.close();
}
