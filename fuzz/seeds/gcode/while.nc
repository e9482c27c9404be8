; expect: 2:1: error: macro B
WHILE [#1 LT 10] DO1
END1
