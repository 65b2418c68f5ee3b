//! What the webviews' HTML needs: escaping and the nonce of their content security policy.
import * as crypto from 'node:crypto';

export function escapeHtml(text: string): string {
  return text.replace(/[&<>"']/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' })[c]!);
}

/** A fresh nonce: only the scripts and styles that carry it run in a webview. */
export function nonce(): string {
  return crypto.randomBytes(16).toString('base64');
}
