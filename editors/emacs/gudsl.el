;;; gudsl.el --- GU-DSL mode with the gudsl language server through eglot  -*- lexical-binding: t; -*-

;; Emacs 29 or newer (eglot is built in).  Load it from your init file:
;;   (load "/path/to/editors/emacs/gudsl.el")
;; and, when `gudsl' is not on PATH:
;;   (setq gudsl-server-command '("/path/to/gudsl" "lsp"))
;; Opening a .gudsl file starts `gudsl lsp' for its project (M-x eglot-ensure runs on the mode's
;; hook): diagnostics through Flymake, completion, xref, rename, formatting, code actions.

;;; Code:

(require 'eglot)

(defgroup gudsl nil "GU-DSL modelling language." :group 'languages)

(defcustom gudsl-server-command '("gudsl" "lsp")
  "The command that starts the GU-DSL language server."
  :type '(repeat string))

(defvar gudsl-mode-syntax-table
  (let ((table (make-syntax-table)))
    (modify-syntax-entry ?/ ". 124b" table)
    (modify-syntax-entry ?* ". 23" table)
    (modify-syntax-entry ?\n "> b" table)
    (modify-syntax-entry ?_ "w" table)
    table)
  "Syntax table of `gudsl-mode': C comments, names with underscores.")

(defconst gudsl-font-lock-keywords
  `((,(regexp-opt '("ClassDiagram" "ActivityDiagram" "ComponentDiagram" "ComponentInstanceDiagram"
                    "class" "interface" "enum" "attribute" "extends" "implements" "import"
                    "public" "protected" "private" "abstract" "const" "global" "static"
                    "action" "decision" "fork" "join" "calc" "calcRange" "loop" "loopWindow" "final"
                    "if" "else" "for" "do" "return" "break" "continue" "call" "behavior" "var" "new")
                  'symbols)
     . font-lock-keyword-face))
  "Reserved keywords of GU-DSL and the node and diagram keywords (eglot in Emacs 29 reads no
semantic tokens, so a name spelled like a contextual keyword is coloured as one).")

;;;###autoload
(define-derived-mode gudsl-mode prog-mode "GU-DSL"
  "Major mode for GU-DSL models."
  (setq-local comment-start "// ")
  (setq-local comment-end "")
  (setq-local font-lock-defaults '(gudsl-font-lock-keywords))
  (setq-local indent-tabs-mode nil)
  (setq-local tab-width 4))

;;;###autoload
(add-to-list 'auto-mode-alist '("\\.gudsl\\'" . gudsl-mode))

(add-to-list 'eglot-server-programs `(gudsl-mode . ,(lambda (&optional _interactive) gudsl-server-command)))
(add-hook 'gudsl-mode-hook #'eglot-ensure)

(provide 'gudsl)
;;; gudsl.el ends here
