#!/usr/bin/env node
// A test learning record store: the xAPI 1.0.3 statements resource on 127.0.0.1, checking each
// statement with Learning Locker's validation package (@learninglocker/xapi-validation), for
// the tests of sending the training record's outbox. Not a product: one process, one file.
//
//   node test_lrs.js --store FILE [--port N] [--key K --secret S] [--exit-after N]
//       Serves PUT/POST/GET {/xapi}/statements and GET /xapi/about. Prints
//       "listening on PORT" once ready (--port 0, the default: a free port). Statements are
//       kept in FILE (one JSON line each, synced) so a restarted server still has them; every
//       answered or dropped request is logged to FILE.log as a JSON line
//       {"id", "outcome"} with outcome stored | same | conflict | invalid | unauthorized |
//       dropped. --exit-after N: after storing the N-th new statement of this run, the server
//       drops the connection unanswered and exits (an outage in mid-queue: stored, not
//       acknowledged).
//   node test_lrs.js --validate FILE
//       Validates a JSON array of statements (acdr report --format xapi); prints how many
//       passed, and each problem; exit 0 only when all pass.
'use strict';
const fs = require('fs');
const http = require('http');
const path = require('path');

const validate = require(path.join(__dirname, 'node_modules', '@learninglocker', 'xapi-validation'))
  .default;

function parseArgs(argv) {
  const args = { port: 0, key: '', secret: '', exitAfter: 0, store: '', validate: '' };
  for (let i = 0; i < argv.length; i += 2) {
    const [name, value] = [argv[i], argv[i + 1]];
    if (value === undefined) throw new Error(`${name}: missing value`);
    if (name === '--port') args.port = Number(value);
    else if (name === '--key') args.key = value;
    else if (name === '--secret') args.secret = value;
    else if (name === '--exit-after') args.exitAfter = Number(value);
    else if (name === '--store') args.store = value;
    else if (name === '--validate') args.validate = value;
    else throw new Error(`unknown option ${name}`);
  }
  return args;
}

// The problems xapi-validation finds in one statement, as "path: problem" lines.
function problems(statement) {
  return validate(statement).map((w) => {
    const where = (w.path || []).join('.');
    return `${where}: ${w.constructor.name}${w.data !== undefined ? ' ' + JSON.stringify(w.data) : ''}`;
  });
}

// Key order does not make two statements different.
function canonical(value) {
  if (Array.isArray(value)) return value.map(canonical);
  if (value && typeof value === 'object') {
    const out = {};
    for (const k of Object.keys(value).sort()) out[k] = canonical(value[k]);
    return out;
  }
  return value;
}

function runValidate(file) {
  const statements = JSON.parse(fs.readFileSync(file, 'utf8'));
  if (!Array.isArray(statements)) throw new Error(`${file}: expected a JSON array of statements`);
  let failed = 0;
  statements.forEach((s, i) => {
    const found = problems(s);
    if (found.length > 0) {
      failed += 1;
      console.log(`statement ${i} (${s.id}): ${found.join('; ')}`);
    }
  });
  console.log(`${statements.length - failed} of ${statements.length} statements pass xapi-validation`);
  process.exit(failed === 0 && statements.length > 0 ? 0 : 1);
}

function serve(args) {
  if (!args.store) throw new Error('--store FILE is required');
  const stored = new Map();  // id -> canonical JSON text
  if (fs.existsSync(args.store)) {
    for (const line of fs.readFileSync(args.store, 'utf8').split('\n')) {
      if (line.trim() === '') continue;
      const entry = JSON.parse(line);
      stored.set(entry.id, JSON.stringify(canonical(entry.statement)));
    }
  }
  const storeFd = fs.openSync(args.store, 'a');
  const logFd = fs.openSync(args.store + '.log', 'a');
  let storedThisRun = 0;

  const log = (id, outcome) => {
    fs.writeSync(logFd, JSON.stringify({ id, outcome }) + '\n');
    fs.fsyncSync(logFd);
  };
  const answer = (res, status, body) => {
    const headers = { 'X-Experience-API-Version': '1.0.3' };
    if (body === undefined) {
      res.writeHead(status, headers);
      res.end();
    } else {
      headers['Content-Type'] = 'application/json';
      res.writeHead(status, headers);
      res.end(JSON.stringify(body));
    }
  };
  const authorised = (req) => {
    if (!args.key) return true;
    const expected = 'Basic ' + Buffer.from(`${args.key}:${args.secret}`).toString('base64');
    return req.headers.authorization === expected;
  };

  // Stores one statement whose id is known. Returns [status, body] or null for "dropped".
  const put = (id, statement) => {
    if (statement.id !== undefined && statement.id !== id) {
      log(id, 'invalid');
      return [400, { message: `statement id ${statement.id} differs from statementId ${id}` }];
    }
    const full = Object.assign({}, statement, { id });
    const found = problems(full);
    if (found.length > 0) {
      log(id, 'invalid');
      return [400, { message: 'the statement is not valid xAPI', warnings: found }];
    }
    const text = JSON.stringify(canonical(full));
    if (stored.has(id)) {
      const same = stored.get(id) === text;
      log(id, same ? 'same' : 'conflict');
      return same ? [204] : [409, { message: `a different statement with id ${id} is stored` }];
    }
    fs.writeSync(storeFd, JSON.stringify({ id, statement: full }) + '\n');
    fs.fsyncSync(storeFd);
    stored.set(id, text);
    storedThisRun += 1;
    if (args.exitAfter > 0 && storedThisRun >= args.exitAfter) {
      log(id, 'dropped');
      return null;
    }
    log(id, 'stored');
    return [204];
  };

  const server = http.createServer((req, res) => {
    const url = new URL(req.url, 'http://127.0.0.1');
    const route = url.pathname.replace(/^\/xapi/i, '').replace(/\/$/, '');
    let body = '';
    req.setEncoding('utf8');
    req.on('data', (chunk) => { body += chunk; });
    req.on('end', () => {
      if (route === '/about') return answer(res, 200, { version: ['1.0.3'] });
      if (route !== '/statements') return answer(res, 404, { message: `no resource ${url.pathname}` });
      const id = url.searchParams.get('statementId') || '';
      if (!authorised(req)) {
        log(id, 'unauthorized');
        return answer(res, 401, { message: 'unknown key or wrong secret' });
      }
      const version = req.headers['x-experience-api-version'] || '';
      if (!/^1\.0(\.\d+)?$/.test(version)) {
        log(id, 'invalid');
        return answer(res, 400, { message: `X-Experience-API-Version '${version}' is not 1.0.x` });
      }
      if (req.method === 'GET') {
        if (id) {
          const text = stored.get(id);
          return text ? answer(res, 200, JSON.parse(text)) : answer(res, 404, { message: 'no such statement' });
        }
        return answer(res, 200, { statements: [...stored.values()].map((t) => JSON.parse(t)), more: '' });
      }
      let parsed;
      try {
        parsed = JSON.parse(body);
      } catch (e) {
        log(id, 'invalid');
        return answer(res, 400, { message: `the body is not JSON: ${e.message}` });
      }
      let result;
      if (req.method === 'PUT') {
        if (!id) {
          log(id, 'invalid');
          return answer(res, 400, { message: 'PUT needs the statementId parameter' });
        }
        result = put(id, parsed);
      } else if (req.method === 'POST') {
        const list = Array.isArray(parsed) ? parsed : [parsed];
        const ids = [];
        for (const s of list) {
          if (typeof s.id !== 'string') {
            log('', 'invalid');
            return answer(res, 400, { message: 'this test store needs statements with ids' });
          }
          result = put(s.id, s);
          if (result === null || result[0] !== 204) break;
          ids.push(s.id);
        }
        if (result !== null && result[0] === 204) result = [200, ids];
      } else {
        return answer(res, 405, { message: `${req.method} is not supported here` });
      }
      if (result === null) {
        // The outage: stored, never acknowledged.
        req.socket.destroy();
        server.close();
        process.exit(0);
      }
      return answer(res, result[0], result[1]);
    });
  });
  server.keepAliveTimeout = 30000;
  server.listen(args.port, '127.0.0.1', () => {
    process.stdout.write(`listening on ${server.address().port}\n`);
  });
  const stop = () => { server.close(); process.exit(0); };
  process.on('SIGTERM', stop);
  process.on('SIGINT', stop);
}

try {
  const args = parseArgs(process.argv.slice(2));
  if (args.validate) runValidate(args.validate);
  else serve(args);
} catch (e) {
  process.stderr.write(`test_lrs.js: ${e.message}\n`);
  process.exit(2);
}
