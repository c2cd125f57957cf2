#!/usr/bin/perl
# Doxygen INPUT_FILTER of the generated reference (tools/docs/reference.py): in comments, the
# placeholders of prose (<stem>, <joint type>, #tm-error) are text, not HTML tags or links.
while (my $line = <>) {
  if ($line =~ m{^(.*?///<?)(.*)$}s) {
    my ($code, $text) = ($1, $2);
    $text =~ s/<(?=[A-Za-z])/\\</g;
    $text =~ s/(?<=[A-Za-z0-9_ .*])>/\\>/g;
    $text =~ s/(?<![\w\\])#(?=[A-Za-z])/\\#/g;
    $line = $code . $text;
  }
  print $line;
}
