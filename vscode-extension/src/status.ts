//! The status bar item: the server's state (starting, ready, stopped, failed to start) and the
//! long work under way (a run), with the log one click away.
import * as vscode from 'vscode';
import { State } from 'vscode-languageclient/node';
import type { ServerBinary } from './server';

export class StatusItem implements vscode.Disposable {
  private readonly item = vscode.window.createStatusBarItem('gudsl.status', vscode.StatusBarAlignment.Left, 10);
  private server = '$(loading~spin) GU-DSL';
  private tooltip = 'GU-DSL language server: starting';
  private work: string | undefined;

  constructor() {
    this.item.name = 'GU-DSL';
    this.item.command = 'gudsl.showServerLog';
    this.update();
    this.item.show();
  }

  serverState(state: State, binary: ServerBinary): void {
    const from = `${binary.command} (${binary.origin === 'setting' ? 'gudsl.server.path' : binary.origin === 'bundled' ? 'shipped with the extension' : 'on PATH'})`;
    switch (state) {
      case State.Starting:
        this.server = '$(loading~spin) GU-DSL';
        this.tooltip = `GU-DSL language server: starting ${from}`;
        break;
      case State.Running:
        this.server = '$(check) GU-DSL';
        this.tooltip = `GU-DSL language server: ready — ${from}`;
        break;
      case State.Stopped:
        this.server = '$(circle-slash) GU-DSL';
        this.tooltip = `GU-DSL language server: stopped — ${from}. Run "GU-DSL: Restart Server".`;
        break;
    }
    this.item.backgroundColor = undefined;
    this.update();
  }

  failed(binary: ServerBinary, why: string): void {
    this.server = '$(error) GU-DSL';
    this.tooltip = `GU-DSL language server did not start: ${binary.command}: ${why}`;
    this.item.backgroundColor = new vscode.ThemeColor('statusBarItem.errorBackground');
    this.update();
  }

  /** Long work under way (`undefined`: none), shown after the server's state. */
  working(what: string | undefined): void {
    this.work = what;
    this.update();
  }

  private update(): void {
    this.item.text = this.work ? `${this.server} $(sync~spin) ${this.work}` : this.server;
    this.item.tooltip = this.work ? `${this.tooltip}\n${this.work}` : this.tooltip;
  }

  dispose(): void {
    this.item.dispose();
  }
}
