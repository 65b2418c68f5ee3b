// The TextMate grammar against the parser, over every sample: the server's semantic tokens say
// which words are keywords and which are names; the grammar must colour a contextual keyword
// (`start`, `target`, `filter`, …) as a keyword exactly where the server says it is one, every
// reserved keyword as a keyword, and the names of declared classes, interfaces, enums, methods
// and activity nodes as entity names. Prints each disagreement; exits 1 if there is one.
//   node tests/grammar/samples.mjs path/to/gudsl path/to/samples [more folders…]
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';
import oniguruma from 'vscode-oniguruma';
import textmate from 'vscode-textmate';

const here = path.dirname(fileURLToPath(import.meta.url));
const extension = path.join(here, '..', '..');
const [gudsl, ...folders] = process.argv.slice(2);
const samples = folders[0];
if (!gudsl || !samples) {
  console.error('usage: node samples.mjs path/to/gudsl path/to/samples [more folders…]');
  process.exit(2);
}

// The parser's keyword table (model/tests/sourcegen/kinds.rs).
const CONTEXTUAL = new Set(('ClassDiagram ActivityDiagram ComponentDiagram ComponentInstanceDiagram source filter sink provider processor self ' +
  'aggregation composition global shared out read write static swimlane owner start final action decision fork join loopWindow calc ' +
  'calcRange behavior loopwindow2D loopwindow3D port async buffered target instantiates').split(' '));
const LEGEND = ['keyword', 'comment', 'string', 'number', 'operator', 'namespace', 'class', 'interface', 'enum', 'enumMember', 'type',
  'function', 'method', 'property', 'parameter', 'variable', 'decorator'];
const KEYWORDISH = /^(keyword|storage|support\.type|constant\.language|variable\.language)\./;

// --- the grammar, as VS Code loads it
const wasm = fs.readFileSync(path.join(extension, 'node_modules', 'vscode-oniguruma', 'release', 'onig.wasm')).buffer;
await oniguruma.loadWASM(wasm);
const registry = new textmate.Registry({
  onigLib: Promise.resolve({ createOnigScanner: (p) => new oniguruma.OnigScanner(p), createOnigString: (s) => new oniguruma.OnigString(s) }),
  loadGrammar: async () => textmate.parseRawGrammar(fs.readFileSync(path.join(extension, 'syntaxes', 'gudsl.tmLanguage.json'), 'utf8'), 'gudsl.tmLanguage.json'),
});
const grammar = await registry.loadGrammar('source.gudsl');

/** The scopes of every character of every line. */
function scopesOf(text) {
  let stack = textmate.INITIAL;
  return text.split('\n').map((line) => {
    const result = grammar.tokenizeLine(line, stack);
    stack = result.ruleStack;
    const perChar = [];
    for (const token of result.tokens) for (let i = token.startIndex; i < token.endIndex; i++) perChar[i] = token.scopes;
    return perChar;
  });
}

// --- the server, over stdio
const server = spawn(gudsl, ['lsp'], { stdio: ['pipe', 'pipe', 'inherit'] });
let buffer = Buffer.alloc(0);
let nextId = 0;
const waiting = new Map();
server.stdout.on('data', (chunk) => {
  buffer = Buffer.concat([buffer, chunk]);
  for (;;) {
    const end = buffer.indexOf('\r\n\r\n');
    if (end < 0) return;
    const length = Number(/Content-Length: (\d+)/i.exec(buffer.subarray(0, end).toString())[1]);
    if (buffer.length < end + 4 + length) return;
    const message = JSON.parse(buffer.subarray(end + 4, end + 4 + length).toString());
    buffer = buffer.subarray(end + 4 + length);
    if (message.id !== undefined && waiting.has(message.id) && message.method === undefined) {
      waiting.get(message.id)(message);
      waiting.delete(message.id);
    } else if (message.id !== undefined && message.method) {
      send({ jsonrpc: '2.0', id: message.id, result: null }); // workDoneProgress/create, registrations
    }
  }
});
function send(message) {
  const body = Buffer.from(JSON.stringify(message));
  server.stdin.write(`Content-Length: ${body.length}\r\n\r\n`);
  server.stdin.write(body);
}
function request(method, params) {
  const id = ++nextId;
  send({ jsonrpc: '2.0', id, method, params });
  return new Promise((resolve, reject) => waiting.set(id, (m) => (m.error ? reject(new Error(`${method}: ${m.error.message}`)) : resolve(m.result))));
}
const notify = (method, params) => send({ jsonrpc: '2.0', method, params });

await request('initialize', {
  processId: process.pid,
  rootUri: pathToFileURL(samples).href,
  capabilities: { textDocument: { semanticTokens: { requests: { full: true }, tokenTypes: LEGEND, tokenModifiers: ['declaration'], formats: ['relative'] } } },
});
notify('initialized', {});

const files = [];
function walk(dir) {
  for (const entry of fs.readdirSync(dir, { withFileTypes: true }).sort((a, b) => a.name.localeCompare(b.name))) {
    const full = path.join(dir, entry.name);
    if (entry.isDirectory()) walk(full);
    else if (entry.name.endsWith('.gudsl')) files.push(full);
  }
}
folders.forEach((folder) => walk(folder));

const problems = [];
const counts = { contextualKeywords: 0, contextualNames: 0, reserved: 0, declarations: 0 };
for (const file of files) {
  const text = fs.readFileSync(file, 'utf8');
  const uri = pathToFileURL(file).href;
  notify('textDocument/didOpen', { textDocument: { uri, languageId: 'gudsl', version: 1, text } });
  const { data } = await request('textDocument/semanticTokens/full', { textDocument: { uri } });
  const lines = text.split('\n');
  const scopes = scopesOf(text);
  let line = 0;
  let start = 0;
  for (let i = 0; i < data.length; i += 5) {
    line += data[i];
    start = data[i] === 0 ? start + data[i + 1] : data[i + 1];
    const word = lines[line].slice(start, start + data[i + 2]);
    const type = LEGEND[data[i + 3]];
    const declaration = (data[i + 4] & 1) === 1;
    const at = (scopes[line][start] ?? []).filter((s) => s !== 'source.gudsl');
    const where = `${path.relative(process.cwd(), file)}:${line + 1}:${start + 1} \`${word}\``;
    const keywordish = at.some((s) => KEYWORDISH.test(s));
    if (type === 'keyword') {
      if (CONTEXTUAL.has(word)) counts.contextualKeywords++;
      else counts.reserved++;
      if (!keywordish) problems.push(`${where}: a keyword, coloured as ${at.join(' ') || 'nothing'}`);
    } else if (/^[A-Za-z_]\w*$/.test(word) && (CONTEXTUAL.has(word) || ['class', 'interface', 'enum', 'method', 'function', 'property', 'variable', 'parameter'].includes(type))) {
      if (CONTEXTUAL.has(word)) counts.contextualNames++;
      if (keywordish && !at.some((s) => s.startsWith('support.type'))) problems.push(`${where}: a ${type}, coloured as a keyword (${at.join(' ')})`);
    }
    if (declaration && ['class', 'interface', 'enum'].includes(type)) {
      counts.declarations++;
      if (!at.some((s) => s.startsWith('entity.name.type'))) problems.push(`${where}: a ${type} declared, coloured as ${at.join(' ') || 'nothing'}`);
    }
    if (declaration && ['method', 'function'].includes(type)) {
      counts.declarations++;
      if (!at.some((s) => s.startsWith('entity.name.function'))) problems.push(`${where}: a ${type} declared, coloured as ${at.join(' ') || 'nothing'}`);
    }
  }
}
await request('shutdown', null);
notify('exit', null);
for (const p of problems) console.log(`FAIL ${p}`);
console.log(
  `${files.length} files: ${counts.contextualKeywords} contextual keywords used as keywords, ${counts.contextualNames} as names, ` +
    `${counts.reserved} reserved keywords, ${counts.declarations} declared names; ${problems.length} disagreement(s) with the parser`,
);
process.exit(problems.length ? 1 : 0);
