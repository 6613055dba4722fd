// Drives the page at GET / in headless Chromium as a person would: choose a file, wait
// for the job to end, look at the canvas. Usage: node page_test.mjs URL MESH [MESH.gltf
// RESOURCES...]. Fails (exit 1) on a console error, a page error, a status other than
// succeeded, a blank canvas, or missing downloads. With EXPECT_TEXTURE=1 (the generated
// textured mesh: red, green, blue and white squares) the sphere view must show the
// texture's red and green, which the page's plain colours do not have.
import { launchBrowser, openPage } from './browser.mjs';

const [url, ...files] = process.argv.slice(2);
const fail = (message) => { console.error(`FAIL: ${message}`); process.exitCode = 1; };

const browser = await launchBrowser();
try {
  const page = await openPage(browser, { width: 1280, height: 900 });
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('requestfailed', (r) => {
    // The event stream is closed by the page itself once the job ends.
    if (!r.url().endsWith('/events')) errors.push(`request failed: ${r.url()}`);
  });

  await page.goto(url);
  const inputs = await page.locator('input[type="file"]').count();
  if (inputs !== 1) fail(`expected one file input, found ${inputs}`);
  const start = Date.now();
  await page.locator('input[type="file"]').setInputFiles(files);
  await page.waitForFunction(
    () => !['idle', 'submitting', 'queued', 'running'].includes(document.body.dataset.status),
    null, { timeout: 120000 });
  const status = await page.evaluate(() => document.body.dataset.status);
  console.log(`status ${status} after ${((Date.now() - start) / 1000).toFixed(1)} s`);
  if (status !== 'succeeded') fail(`job ended ${status}: ${await page.locator('#error').textContent()}`);

  // Non-blank: the canvas, read back, has many distinct colours (a mesh, shaded), not one.
  await page.waitForTimeout(500);
  const colours = await page.evaluate(() => {
    const source = document.querySelector('canvas');
    const copy = Object.assign(document.createElement('canvas'), { width: 160, height: 120 });
    const context = copy.getContext('2d');
    context.drawImage(source, 0, 0, 160, 120);
    const data = context.getImageData(0, 0, 160, 120).data;
    const seen = new Set();
    for (let i = 0; i < data.length; i += 4) seen.add((data[i] >> 3) << 10 | (data[i + 1] >> 3) << 5 | data[i + 2] >> 3);
    return seen.size;
  });
  console.log(`canvas: ${colours} distinct colours`);
  if (colours < 20) fail(`the canvas looks blank (${colours} colours)`);

  const downloads = await page.locator('#downloads a').allTextContents();
  console.log(`downloads: ${downloads.join(', ')}`);
  for (const name of ['sphere.glb', 'metrics.json', 'remesh.glb', 'morph.glb'])
    if (!downloads.includes(name)) fail(`no download link for ${name}`);
  const verdict = await page.locator('#verdict').textContent();
  if (!verdict.startsWith('Bijective')) fail(`verdict: ${verdict}`);

  if (process.env.EXPECT_TEXTURE) {
    await page.locator('#views [data-view="sphere"]').click();
    await page.waitForTimeout(500);
    const [red, green] = await page.evaluate(() => {
      const source = document.querySelector('canvas');
      const copy = Object.assign(document.createElement('canvas'), { width: 320, height: 240 });
      const context = copy.getContext('2d');
      context.drawImage(source, 0, 0, 320, 240);
      const d = context.getImageData(0, 0, 320, 240).data;
      let r = 0, g = 0;
      for (let i = 0; i < d.length; i += 4) {
        r += d[i] > 120 && d[i + 1] < 60 && d[i + 2] < 60;
        g += d[i + 1] > 120 && d[i] < 60 && d[i + 2] < 60;
      }
      return [r, g];
    });
    console.log(`sphere view: ${red} red and ${green} green pixels of the input's texture`);
    if (red < 50 || green < 50) fail('the sphere does not show the input\'s texture');
  }

  // A mesh mapped as it is (not wrapped) has no original-beside-envelope view.
  if (!(await page.locator('#views [data-view="compare"]').isHidden()))
    fail('the "Original | envelope" view is offered for a mesh that was not wrapped');

  // Every view draws, and the heat map and the morph slider work.
  for (const view of ['input', 'remesh', 'morph']) {
    const button = page.locator(`#views [data-view="${view}"]`);
    if (await button.isDisabled()) { fail(`view ${view} is not available`); continue; }
    await button.click();
  }
  await page.locator('#heat').check();
  await page.locator('#morph').fill('1');
  await page.waitForTimeout(300);
  await page.locator('#morph').fill('0');  // the mesh again, coloured by its distortion
  await page.waitForTimeout(300);
  if (process.env.SCREENSHOT) await page.screenshot({ path: process.env.SCREENSHOT });
  if (errors.length) fail(`console errors:\n  ${errors.join('\n  ')}`);
} finally {
  await browser.close();
}
