#!/usr/bin/env node
// A toy Dala functional layer speaking untimely/1 on stdio (docs/protocol.md, docs/adapters.md).
// Node.js >= 18, no npm dependencies. Run by the bench:
//   python -m harness run missions/dala/golden.mission --sut toy=cmd:"node examples/node/adapter.js"
// Every exec request is accepted and runs for a while (mission seconds, scaled by the hello's
// time_scale); the long-running services run until their module's Stop interrupts them.
'use strict';
const readline = require('node:readline');

const SECONDS = { Init: 0.5, Stop: 0.05, Reset: 0.2, OneShot: 0.2, Point: 2, GotoPosition: 3 };
const duration = (service, args) => service === 'Communication' ? args.duration : SECONDS[service];
const CODES = ['ok', 'wait_init', 'interrupted', 'link_lost']; // every code this layer can reply
const MOVING = 'GotoPosition'; // the rover moves: a running Communication loses its link

let kinds = null; // module -> service -> kind, from the bench's hello
let scale = 1;
let started = 0n;
const initialised = new Set(); // modules whose Init ended ok
const running = new Map(); // request id -> { module, service, timer }

const send = (message) => process.stdout.write(JSON.stringify(message) + '\n');
const now = () => Math.round(Number(process.hrtime.bigint() - started) / 1e3 * scale) / 1e6; // mission s
const internal = (id, kind, code) => send({ op: 'internal', id, kind, t: now(), ...(code && { code }) });

function reply(id, kind, code) {
  internal(id, kind, code);
  send({ op: 'reply', id, kind, ...(code && { code }) });
}

function finish(id, code) { // the one place a final reply of an activity is sent
  const activity = running.get(id);
  running.delete(id);
  clearTimeout(activity.timer);
  if (activity.service === 'Init' && code === 'ok') initialised.add(activity.module);
  reply(id, 'final', code);
}

function interruptAll(module, services, code) {
  for (const [id, a] of running) if (a.module === module && services(a.service)) finish(id, code);
}

function hello(message) {
  if (message.proto !== 'untimely/1') return fail(`proto ${JSON.stringify(message.proto)} is not untimely/1`);
  const missing = CODES.filter((code) => !(code in message.interface.replies));
  if (missing.length) return fail(`the reply catalogue lacks ${missing.join(', ')}, which this layer replies`);
  kinds = message.interface.modules;
  scale = message.time_scale;
  started = process.hrtime.bigint();
  send({ op: 'hello', proto: 'untimely/1', sut: `node toy Dala layer 1 (node ${process.version})`,
    caps: ['internal', 'world'] });
}

function request({ id, module, service, args }) {
  const kind = kinds[module]?.[service];
  if (!kind) return fail(`request ${id}: the interface has no service ${module}.${service}`);
  internal(id, 'request');
  if (kind === 'control') return reply(id, 'final', 'ok');
  if (kind === 'exec' && !initialised.has(module)) return reply(id, 'final', 'wait_init');
  // a Stop ends every activity of its module; any exec ends an older one of the same service
  interruptAll(module, (s) => s !== 'Init' && (service === 'Stop' || s === service), 'interrupted');
  if (kind === 'exec') reply(id, 'intermediate');
  if (service === MOVING && [...running.values()].some((a) => a.service === 'Communication')) {
    send({ op: 'world', t: now(), kind: 'moved_while_linked', detail: { request: id } });
    interruptAll('antenna', (s) => s === 'Communication', 'link_lost');
  }
  const seconds = duration(service, args);
  const timer = seconds === undefined ? null : setTimeout(() => finish(id, 'ok'), seconds * 1000 / scale);
  running.set(id, { module, service, timer });
}

function fail(message) {
  send({ op: 'error', message });
  process.exit(1);
}

const lines = readline.createInterface({ input: process.stdin });
lines.on('line', (line) => {
  const message = JSON.parse(line);
  if (message.op === 'hello') hello(message);
  else if (message.op === 'ping') send({ op: 'pong', id: message.id });
  else if (message.op === 'bye') process.exit(0);
  else if (message.op === 'request') kinds ? request(message) : fail('a request before hello');
});
lines.on('close', () => process.exit(0)); // the bench closed stdin: the run is over
