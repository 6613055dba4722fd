// The headless Chromium every page test drives: Debian's (or $CHROMIUM), software WebGL
// (SwiftShader: no GPU here), and none of the browser's own network traffic, so a test
// sees only the service's requests.
import { chromium } from 'playwright-core';

export function launchBrowser() {
  return chromium.launch({
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
      '--disable-quic', '--no-first-run', '--disable-background-networking',
      '--disable-component-update', '--disable-sync'],
  });
}

// How long a page may take to load (default 30 s): on a 2-core machine running two CI
// runs at once, three.js's 100 KB module once took 10 s to be served, and a load timed out.
// The same budget as the tests' waits for a job.
export const kLoadTimeoutMs = 120000;

// A page of `browser` with that load budget.
export async function openPage(browser, viewport) {
  const page = await browser.newPage({ viewport });
  page.setDefaultNavigationTimeout(kLoadTimeoutMs);
  return page;
}
