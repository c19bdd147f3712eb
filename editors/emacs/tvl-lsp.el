;;; tvl-lsp.el --- TVL models and ROS launch files with the tvl-lsp server (eglot)  -*- lexical-binding: t; -*-

;; Usage (init.el), Emacs 28 with eglot (Debian: elpa-eglot) or Emacs 29+:
;;   (add-to-list 'load-path "/path/to/tvl-lsp/editors/emacs")
;;   (require 'tvl-lsp)
;;   (setq tvl-lsp-command '("/path/to/tvl-lsp/.venv/bin/tvl-lsp"))  ; if not on PATH
;;   (add-hook 'tvl-mode-hook #'eglot-ensure)
;;   (add-hook 'roslaunch-mode-hook #'eglot-ensure)

;;; Code:

(require 'eglot)
(require 'nxml-mode)
(require 'project)

(defgroup tvl-lsp nil "TVL feature models and ROS launch files." :group 'languages)

(defcustom tvl-lsp-command '("tvl-lsp")
  "Command that starts the tvl-lsp language server (LSP on stdio)."
  :type '(repeat string))

(defvar tvl-mode-syntax-table
  (let ((st (make-syntax-table)))
    (modify-syntax-entry ?/ ". 124b" st)
    (modify-syntax-entry ?* ". 23" st)
    (modify-syntax-entry ?\n "> b" st)
    (modify-syntax-entry ?_ "_" st)
    (modify-syntax-entry ?\" "\"" st)
    st))

(defconst tvl-font-lock-keywords
  `((,(regexp-opt '("root" "group" "include") 'words) . font-lock-keyword-face)
    (,(regexp-opt '("allOf" "oneOf" "someOf" "allof" "oneof" "someof") 'words) . font-lock-keyword-face)
    ("\\<\\(?:ifIn\\|ifOut\\|ifin\\|ifout\\)\\s-*:" . font-lock-keyword-face)
    (,(regexp-opt '("opt" "shared" "const" "constant") 'words) . font-lock-builtin-face)
    (,(regexp-opt '("int" "real" "bool" "enum" "struct") 'words) . font-lock-type-face)
    (,(regexp-opt '("true" "false") 'words) . font-lock-constant-face)
    (,(regexp-opt '("this" "parent" "children" "selectedChildren" "selectedchildren") 'words) . font-lock-variable-name-face)
    ("\\<root\\s-+\\([A-Za-z_][A-Za-z0-9_]*\\)" 1 font-lock-type-face)
    ("^\\s-*\\([A-Za-z_][A-Za-z0-9_]*\\)\\s-*{" 1 font-lock-type-face)))

;;;###autoload
(define-derived-mode tvl-mode prog-mode "TVL"
  "Major mode for TVL feature models."
  (setq-local comment-start "// ")
  (setq-local comment-end "")
  (setq-local font-lock-defaults '(tvl-font-lock-keywords)))

;;;###autoload
(define-derived-mode roslaunch-mode nxml-mode "roslaunch"
  "Major mode for ROS 1 launch files (XML).")

;;;###autoload
(progn
  (add-to-list 'auto-mode-alist '("\\.tvl\\'" . tvl-mode))
  (add-to-list 'auto-mode-alist '("\\.launch\\(?:\\.xml\\)?\\'" . roslaunch-mode))
  (add-to-list 'auto-mode-alist '("_launch\\.xml\\'" . roslaunch-mode))
  (add-to-list 'auto-mode-alist '("\\.test\\'" . roslaunch-mode)))

(defun tvl-lsp-project-find (dir)
  "The catkin workspace above DIR: the folder with .catkin_workspace, .catkin_tools or haros*.yaml."
  (let ((root (locate-dominating-file
               dir (lambda (d)
                     (and (file-directory-p d)
                          (or (file-exists-p (expand-file-name ".catkin_workspace" d))
                              (file-exists-p (expand-file-name ".catkin_tools" d))
                              (directory-files d nil "\\`haros.*\\.ya?ml\\'" t)))))))
    (when (and root (memq major-mode '(tvl-mode roslaunch-mode)))
      (cons 'transient (expand-file-name root)))))

(add-hook 'project-find-functions #'tvl-lsp-project-find -50)

(add-to-list 'eglot-server-programs
             `((tvl-mode roslaunch-mode) . ,(lambda (&rest _) tvl-lsp-command)))

(provide 'tvl-lsp)
;;; tvl-lsp.el ends here
