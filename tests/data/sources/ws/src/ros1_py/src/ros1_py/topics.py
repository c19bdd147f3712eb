"""Names shared by the package's nodes."""
CMD_TOPIC = 'cmd_vel'
NAMESPACE = '/robot'
