"""The ROS 1 (roslaunch XML) front end: the symbolic loader (``loader``) and its rules
(``rules``, ``scopes``, ``subst``, ``tags``, ``params``, ``includes``).  It produces the
dialect-independent model of ``tvl_lsp.launch.model``."""
