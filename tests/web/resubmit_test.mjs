// A second file chosen while the first submission is still on its way: the page must end
// showing the second job, whatever order the answers come back in. The first POST is held
// back until the second job has been shown, then let through; once the first job has also
// run, the page is watched 2 s more, in which a page that followed the late answer would
// have replaced the results with the first job's.
// Usage: node resubmit_test.mjs URL FIRST.glb SECOND.glb
import { launchBrowser, openPage } from './browser.mjs';

const [url, first, second] = process.argv.slice(2);
const fail = (message) => { console.error(`FAIL: ${message}`); process.exitCode = 1; };

const browser = await launchBrowser();
try {
  const page = await openPage(browser, { width: 1280, height: 900 });
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  const submitted = [];  // job ids in the order the answers arrived
  page.on('response', async (response) => {
    if (response.request().method() === 'POST' && response.url().endsWith('/v1/jobs') && response.status() === 202)
      submitted.push((await response.json()).id);
  });
  let posts = 0;
  let release;
  const released = new Promise((resolve) => { release = resolve; });
  await page.route('**/v1/jobs', async (route) => {
    if (route.request().method() === 'POST' && posts++ === 0) await released;
    await route.continue();
  });

  await page.goto(url);
  const input = page.locator('input[type="file"]');
  await input.setInputFiles(first);
  await page.waitForTimeout(300);
  await input.setInputFiles(second);
  await page.waitForFunction(
    () => !['idle', 'submitting', 'queued', 'running'].includes(document.body.dataset.status),
    null, { timeout: 120000 });
  release();
  for (let i = 0; i < 600 && submitted.length < 2; ++i) await page.waitForTimeout(100);
  if (submitted.length === 2) {  // the first job runs to its end, then the page has 2 s
    for (let i = 0; i < 600; ++i) {
      const job = await (await page.request.get(new URL(`v1/jobs/${submitted[1]}`, url).href)).json();
      if (!['queued', 'running'].includes(job.status)) break;
      await page.waitForTimeout(100);
    }
    await page.waitForTimeout(2000);
  }
  if (submitted.length !== 2) fail(`expected two accepted submissions, saw ${submitted.length}`);
  const [secondJob, firstJob] = submitted;  // the second was answered first
  const status = await page.evaluate(() => document.body.dataset.status);
  if (status !== 'succeeded') fail(`the page ended ${status}`);
  const href = await page.locator('#downloads a', { hasText: 'sphere.glb' }).getAttribute('href');
  console.log(`jobs ${firstJob} (first, answered late) and ${secondJob}; the page shows ${href}`);
  if (!href?.includes(secondJob)) fail(`the page shows ${href}, not the second job ${secondJob}`);
  if (errors.length) fail(`page errors:\n  ${errors.join('\n  ')}`);
} finally {
  await browser.close();
}
