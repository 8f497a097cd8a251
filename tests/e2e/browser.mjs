// What every browser test shares: Debian's Chromium launched headless (playwright never downloads a
// browser), and a login through the page's own form.
import {chromium} from 'playwright-core';

const kBaseArgs = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
                   '--disable-background-networking', '--disable-component-update', '--disable-sync'];

// `extraArgs` adds flags (autoplay for WebRTC video, no throttling of background tabs, ...).
export function launchChromium(extraArgs = []) {
  return chromium.launch({executablePath: process.env.CHROMIUM || '/usr/bin/chromium', args: [...kBaseArgs, ...extraArgs]});
}

// Logs `user` in at `base` in a new 1480 x 900 context and waits for the page the login leads to
// (`landing`, the lab page by default). `onPageError` receives the page's uncaught errors;
// `initScript` runs in the page before its own scripts; `prepare(page)` before the page is loaded;
// `gotoOptions` is passed to page.goto.
export async function logIn(browser, base, user, password,
                            {onPageError, initScript, prepare, landing = '**/lab.html', gotoOptions} = {}) {
  const context = await browser.newContext({viewport: {width: 1480, height: 900}});
  if (initScript) await context.addInitScript(initScript);
  const page = await context.newPage();
  if (onPageError) page.on('pageerror', onPageError);
  if (prepare) prepare(page);
  await page.goto(base + '/', gotoOptions);
  await page.fill('#user', user);
  await page.fill('#password', password);
  await page.click('#login-button');
  await page.waitForURL(landing);
  return {context, page};
}
