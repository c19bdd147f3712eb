" ROS launch files are XML: indent them as XML.
runtime! indent/xml.vim
