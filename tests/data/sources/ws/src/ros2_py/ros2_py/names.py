CHATTER = 'chatter'
