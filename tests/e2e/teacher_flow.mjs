// End-to-end in a real browser (headless Debian chromium driven by playwright-core) on the simulated
// lab (`labodrone serve`): the teacher's part of the lab page. A student holds control; the teacher
// registers a face from photos taken with the drone's front camera (the simulated teacher's face,
// rendered by `labodrone sim render`; a portrait photo of another size is refused first), chooses it,
// ends the student's turn with a reason the student's page shows, and starts face-follow, which
// takes over control and follows the registered face.
// Usage: node teacher_flow.mjs BASE_URL OUT_DIR FRONTAL_PNG WRONG_SIZE_PNG
import {launchChromium, logIn} from './browser.mjs';

const [base, out, frontalPhoto, wrongSizePhoto] = process.argv.slice(2);
const fail = (msg) => { console.error('FAIL: ' + msg); process.exitCode = 1; };
const browser = await launchChromium();

async function login(user) {
  const {page} = await logIn(browser, base, user, user + '-pass', {onPageError: (e) => fail(`${user}: page error: ${e.message}`)});
  await page.waitForFunction(() => window.labodrone && window.labodrone.connected, null, {timeout: 10000});
  await page.waitForFunction(() => document.getElementById('who').textContent.includes('·'));
  return page;
}

const text = (page, id) => page.evaluate((i) => document.getElementById(i).textContent, id);
const waitText = (page, id, part, timeout = 20000) =>
  page.waitForFunction(([i, p]) => document.getElementById(i).textContent.includes(p), [id, part], {timeout});

try {
  const student = await login('student1');
  if (await student.isVisible('#teacher-panel')) fail('a student sees the teacher panel');
  await student.click('#request-control');
  await waitText(student, 'turn', 'your turn');

  const teacher = await login('teacher');
  await teacher.waitForSelector('#teacher-panel', {state: 'visible'});
  await waitText(teacher, 'people-note', '640x360');
  await waitText(teacher, 'control-state', 'student1 (student) has control for');

  // A photo that is not the front camera's size is refused with the reason.
  await teacher.fill('#person-name', 'ada');
  await teacher.setInputFiles('#frontal-photos', wrongSizePhoto);
  await teacher.click('#register-person');
  await waitText(teacher, 'register-result', 'refused (422)');
  const refusal = await text(teacher, 'register-result');
  if (!refusal.includes("expected the front camera's 640x360")) fail('the refusal does not say why: ' + refusal);

  // The frontal photo registers; the face fit's RMS is shown and the face is listed.
  await teacher.setInputFiles('#frontal-photos', frontalPhoto);
  const started = Date.now();
  await teacher.click('#register-person');
  await waitText(teacher, 'register-result', 'registered ada: fit RMS', 60000);
  const registered = await text(teacher, 'register-result');
  await waitText(teacher, 'people', 'ada');
  console.log(`teacher: ${registered} (${((Date.now() - started) / 1000).toFixed(1)} s from the click)`);
  await teacher.selectOption('#follow-person', 'ada');

  // The student's turn ended with a reason, which the student reads.
  await waitText(teacher, 'end-turn-who', "student1's turn");
  await teacher.fill('#end-turn-reason', 'time to let the next group measure');
  await teacher.click('#end-turn');
  await waitText(student, 'events', 'your turn was ended by teacher: time to let the next group measure');
  await waitText(student, 'turn', 'you are watching');

  // Face-follow: the choice is sent, control taken over, the mission started on ada's face.
  await teacher.click('#start-follow');
  await teacher.waitForFunction(() => window.labodrone.acks.some((a) => a.command === 'find_teacher'), null, {timeout: 20000});
  const ack = await teacher.evaluate(() => window.labodrone.acks.find((a) => a.command === 'find_teacher'));
  if (!ack.accepted || ack.reason !== 'searching for ada') fail('find_teacher: ' + JSON.stringify(ack));
  await waitText(teacher, 'follow-note', 'face-follow follows ada');
  await waitText(teacher, 'control-state', 'teacher (teacher) has control');
  await waitText(student, 'mission', 'find_teacher');
  console.log(`teacher: face-follow ${JSON.stringify(ack)}; student's mission: ${await text(student, 'mission')}, stage: ${await text(student, 'stage')}`);
  await teacher.screenshot({path: out + '/teacher_flow.png', fullPage: true});
  await student.screenshot({path: out + '/teacher_flow_student.png', fullPage: true});
  await teacher.click('#stop');
} catch (e) {
  fail(e.message);
} finally {
  await browser.close();
}
