// The cellc extension: the language client that starts `cellc lsp` for .cell files.
// Everything the editor shows (diagnostics, hover, definitions, completion, formatting)
// comes from the server; this file only starts it.
'use strict';

const vscode = require('vscode');
const { LanguageClient } = require('vscode-languageclient/node');

let client;

function activate(context) {
  const config = vscode.workspace.getConfiguration('cellc');
  const args = ['lsp'];
  for (const dir of config.get('packagePath', [])) {
    args.push('--package-path', dir);
  }
  const run = { command: config.get('path', 'cellc'), args };
  client = new LanguageClient(
    'cellc',
    'cellc',
    { run, debug: run },
    { documentSelector: [{ scheme: 'file', language: 'cell' }] },
  );
  context.subscriptions.push(
    vscode.workspace.onDidChangeConfiguration((e) => {
      if (e.affectsConfiguration('cellc')) {
        vscode.window.showInformationMessage('cellc: reload the window to use the new settings.');
      }
    }),
  );
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
