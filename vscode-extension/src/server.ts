//! Starting and restarting `gudsl lsp`: which binary (setting, the one in the .vsix, `PATH`), the
//! language client over stdio, the code lenses' commands taken over by the extension's own, and
//! `Server`, through which every feature reaches the running client.
import * as fs from 'node:fs';
import * as os from 'node:os';
import * as path from 'node:path';
import * as vscode from 'vscode';
import { LanguageClient, LanguageClientOptions, ServerOptions, State } from 'vscode-languageclient/node';
import { StatusItem } from './status';

/** The server's commands (its `executeCommand` list) that the extension runs itself. */
const LENS_COMMANDS: Record<string, string> = {
  'gudsl.run': 'gudsl.runDiagram',
  'gudsl.runPipeline': 'gudsl.runDiagram',
  'gudsl.showWgsl': 'gudsl.showGeneratedWgsl',
  'gudsl.preview': 'gudsl.toggleLivePreview',
};

/** Where the binary comes from: what `Show Server Log` and error messages name. */
export interface ServerBinary {
  command: string;
  origin: 'setting' | 'bundled' | 'PATH';
}

/** The `gudsl` binary to start: the setting, else the one shipped for this platform, else PATH. */
function findServer(context: vscode.ExtensionContext): ServerBinary {
  const configured = vscode.workspace.getConfiguration('gudsl').get<string | null>('server.path');
  if (configured && configured.trim() !== '') {
    // A bare name (`gudsl-dev`) is looked up on PATH; anything with a folder is a path.
    const bare = !configured.includes('/') && !configured.includes(path.sep) && !configured.startsWith('~');
    return { command: bare ? configured : settingPath(configured), origin: 'setting' };
  }
  const bundled = context.asAbsolutePath(path.join('server', process.platform === 'win32' ? 'gudsl.exe' : 'gudsl'));
  if (fs.existsSync(bundled)) {
    return { command: bundled, origin: 'bundled' };
  }
  return { command: 'gudsl', origin: 'PATH' };
}

/** A path a setting names: `~` is the home folder, a relative path is taken from the first
 * workspace folder (the home folder without one). */
export function settingPath(value: string): string {
  const expanded = value.trim().replace(/^~(?=$|\/|\\)/, os.homedir());
  return path.resolve(vscode.workspace.workspaceFolders?.[0]?.uri.fsPath ?? os.homedir(), expanded);
}

/** A language client for `gudsl lsp`, not yet started. */
function createClient(binary: ServerBinary, output: vscode.LogOutputChannel): LanguageClient {
  const extraArgs = vscode.workspace.getConfiguration('gudsl').get<string[]>('server.extraArgs') ?? [];
  // No `transport`: with `TransportKind.stdio` the client appends `--stdio`; without one it still
  // talks over the child's stdin and stdout (`gudsl lsp` also accepts `--stdio`).
  const run = { command: binary.command, args: ['lsp', ...extraArgs] };
  const serverOptions: ServerOptions = { run, debug: run };
  const clientOptions: LanguageClientOptions = {
    documentSelector: [{ scheme: 'file', language: 'gudsl' }, { scheme: 'untitled', language: 'gudsl' }],
    outputChannel: output,
    // In Restricted Mode the server reads no file a model names and runs nothing; granting
    // trust restarts it (extension.ts).
    initializationOptions: { trusted: vscode.workspace.isTrusted },
    // Errors of the server's start are shown by the extension, with what to do about them.
    initializationFailedHandler: () => false,
    middleware: {
      provideCodeLenses: async (document, token, next) => {
        const lenses = await next(document, token);
        for (const lens of lenses ?? []) {
          const own = lens.command && LENS_COMMANDS[lens.command.command];
          if (lens.command && own) {
            lens.command = { ...lens.command, command: own, arguments: [{ ...lens.command.arguments?.[0], serverCommand: lens.command.command }] };
          }
        }
        return lenses;
      },
    },
  };
  return new LanguageClient('gudsl', 'GU-DSL Language Server', serverOptions, clientOptions);
}

/** The running language client, and what every feature asks it through. */
export class Server {
  client: LanguageClient | undefined;
  binary: ServerBinary | undefined;
  private readonly listeners: ((client: LanguageClient) => void)[] = [];
  private restarting: Promise<void> = Promise.resolve();

  constructor(
    private readonly context: vscode.ExtensionContext,
    readonly output: vscode.LogOutputChannel,
    private readonly status: StatusItem,
  ) {}

  /** Calls `listener` with every client once it runs (now, if one does). */
  onStarted(listener: (client: LanguageClient) => void): void {
    this.listeners.push(listener);
    if (this.client?.state === State.Running) listener(this.client);
  }

  /** The client, once running; an error a command shows when the server is not running. */
  async running(): Promise<LanguageClient> {
    if (this.client?.state === State.Running) return this.client;
    if (this.client?.state === State.Starting) {
      await new Promise<void>((resolve) => {
        const sub = this.client!.onDidChangeState((e) => {
          if (e.newState !== State.Starting) {
            sub.dispose();
            resolve();
          }
        });
      });
      const now = this.client as LanguageClient | undefined;
      if (now?.state === State.Running) return now;
    }
    throw new Error('the GU-DSL language server is not running (see "GU-DSL: Show Server Log")');
  }

  async start(): Promise<void> {
    const binary = findServer(this.context);
    this.binary = binary;
    const client = createClient(binary, this.output);
    this.client = client;
    client.onDidChangeState((e) => this.status.serverState(e.newState, binary));
    this.status.serverState(State.Starting, binary);
    try {
      await client.start();
    } catch (e) {
      this.status.failed(binary, String(e));
      const settings = 'Open Settings';
      const log = 'Show Server Log';
      const where = binary.origin === 'setting' ? `gudsl.server.path = ${binary.command}` : binary.origin === 'bundled' ? binary.command : '`gudsl` on PATH';
      void vscode.window
        .showErrorMessage(`GU-DSL: the language server could not start (${where}): ${errorText(e)}`, settings, log)
        .then((choice) => {
          if (choice === settings) void vscode.commands.executeCommand('workbench.action.openSettings', 'gudsl.server');
          if (choice === log) this.output.show(true);
        });
      return;
    }
    for (const listener of this.listeners) listener(client);
  }

  async stop(): Promise<void> {
    const client = this.client;
    this.client = undefined;
    if (client && client.state !== State.Stopped) {
      await client.stop(2000).catch(() => undefined);
    }
  }

  /** Restarts one after another (a command and a settings change, a double click), each after the
   * client it stops has finished starting: a client stopped while starting would keep running. */
  restart(): Promise<void> {
    this.restarting = this.restarting.then(async () => {
      if (this.client?.state === State.Starting) await this.running().catch(() => undefined);
      await this.stop();
      await this.start();
    });
    return this.restarting;
  }
}

/** A request's failure as a user reads it (JSON-RPC errors carry their message). */
export function errorText(e: unknown): string {
  if (e instanceof Error) return e.message;
  if (e && typeof e === 'object' && 'message' in e) return String((e as { message: unknown }).message);
  return String(e);
}

