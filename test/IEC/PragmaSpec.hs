-- | CODESYS's conditional compilation (Stref.IEC.Pragma; NX-PRAGMA-1..4,
-- NX-PRAGMA-13..16). Every expected text is written by hand: what stays,
-- and what is turned into spaces.
module IEC.PragmaSpec (spec) where

import Data.Text (Text)
import qualified Data.Text as T
import Stref.IEC.Pragma
import Stref.Policy (NestedComments (..))
import Stref.Syntax (Pos (..))
import Stref.Verification (VerificationError (..))
import Test.Hspec

-- | The text as spaces, newlines, carriage returns and tabs kept.
b :: Text -> Text
b = T.map (\c -> if c `elem` ("\n\r\t" :: String) then c else ' ')

-- | The lines that keep some text, stripped.
kept :: Text -> Either (Text, Int, Int) [Text]
kept src = case preprocess src of
  Left e -> Left (err e)
  Right out -> Right (filter (not . T.null) (map T.strip (T.lines out)))

err :: VerificationError -> (Text, Int, Int)
err (VerificationError k (Pos l c) _) = (k, l, c)

failure :: Text -> Maybe (Text, Int, Int)
failure src = either (Just . err) (const Nothing) (preprocess src)

-- | Whether the section of a condition is compiled after some declarations
-- (at the top level, outside every POU).
holds :: Text -> Text -> Either (Text, Int, Int) Bool
holds decls c = elem "yes := 1;" <$> kept (decls <> "\n{IF " <> c <> "}\nyes := 1;\n{END_IF}\n")

-- | Whether the section of a condition written in the body of the program
-- MAIN is compiled.
inMain :: Text -> Text -> Text -> Either (Text, Int, Int) Bool
inMain before vars c =
  elem "yes := 1;" <$> kept (before <> "\nPROGRAM MAIN\nVAR\n" <> vars <> "\nEND_VAR\n{IF " <> c <> "}\nyes := 1;\n{END_IF}\nEND_PROGRAM\n")

spec :: Spec
spec = describe "conditional compilation (Stref.IEC.Pragma)" $ do
  describe "the text that stays" $ do
    it "is unchanged without conditional pragmas; attribute, message and unknown pragmas stay (NX-PRAGMA-2, NX-PRAGMA-4, NX-PRAGMA-5)" $ do
      let src = "{attribute 'hide'}\nPROGRAM MAIN\nVAR x : INT; {info 'todo'} END_VAR\n{no such pragma} x := 1; {warning 1 'w'}\nEND_PROGRAM\n"
      preprocess src `shouldBe` Right src
    it "turns the pragmas and the region left out into spaces, so that every column stays (NX-PRAGMA-13)" $
      preprocess "x := 1; {IF defined(a)} y := 2; {END_IF} z := 3;"
        `shouldBe` Right ("x := 1; " <> b "{IF defined(a)} y := 2; {END_IF}" <> " z := 3;")
    it "keeps newlines, carriage returns and tabs of the region left out, so that every line stays" $ do
      let out = "{IF defined(a)}\r\n\tx := 1;\r\n{ELSE}\r\n"
      preprocess (out <> "\ty := 2;\r\n{END_IF}\r\nz := 3;")
        `shouldBe` Right (b out <> "\ty := 2;\r\n" <> b "{END_IF}" <> "\r\nz := 3;")
    it "blanks the message pragmas of a region left out, and keeps those of the section taken (NX-PRAGMA-4)" $
      preprocess "{IF defined(a)}{error 'no'}{ELSE}{info 'yes'}{END_IF}"
        `shouldBe` Right (b "{IF defined(a)}{error 'no'}{ELSE}" <> "{info 'yes'}" <> b "{END_IF}")
    it "reads the words of a pragma in any case (NX-PRAGMA-1)" $
      kept "{DEFINE Opt}\n{If Defined (OPT)}\na;\n{Else}\nb;\n{End_If}\n{if DEFINED(opt) and not defined(other)}c;{end_if}" `shouldBe` Right ["a;", "c;"]
    it "allows spaces inside the braces" $
      kept "{ define a }\n{ IF defined(a) }\nx;\n{ ELSE }\ny;\n{ END_IF }" `shouldBe` Right ["x;"]

  describe "sections (NX-PRAGMA-14)" $ do
    it "takes the first section whose condition holds, ELSE when none does" $ do
      let chain = "{IF defined(a)}\nA;\n{ELSIF defined(b)}\nB;\n{ELSIF defined(c)}\nC;\n{ELSE}\nE;\n{END_IF}\n"
      kept ("{define b}{define c}\n" <> chain) `shouldBe` Right ["B;"]
      kept ("{define c}\n" <> chain) `shouldBe` Right ["C;"]
      kept ("{define a}{define c}\n" <> chain) `shouldBe` Right ["A;"]
      kept chain `shouldBe` Right ["E;"]
    it "compiles nothing when no condition holds and there is no ELSE" $
      kept "x;\n{IF defined(a)}\nA;\n{ELSIF defined(b)}\nB;\n{END_IF}\ny;" `shouldBe` Right ["x;", "y;"]
    it "nests: an inner IF counts only inside the outer section taken" $ do
      let src d = d <> "\n{IF defined(a)}\n{IF defined(b)}\nAB;\n{ELSE}\nA;\n{END_IF}\n{ELSE}\n{IF defined(b)}\nB;\n{ELSE}\nNONE;\n{END_IF}\n{END_IF}"
      kept (src "{define a}{define b}") `shouldBe` Right ["AB;"]
      kept (src "{define a}") `shouldBe` Right ["A;"]
      kept (src "{define b}") `shouldBe` Right ["B;"]
      kept (src "") `shouldBe` Right ["NONE;"]
    it "does not read the conditions of an IF inside a region left out" $
      kept "{IF defined(a)}\n{IF this is no condition}\nx;\n{END_IF}\n{END_IF}\ny;" `shouldBe` Right ["y;"]

  describe "define and undefine (NX-PRAGMA-13, NX-PRAGMA-3)" $ do
    it "apply from their position on, in file order" $
      kept "{IF defined(a)}1;{END_IF}\n{define a}\n{IF defined(a)}2;{END_IF}\n{undefine a}\n{IF defined(a)}3;{END_IF}\n{define a}\n{IF defined(a)}4;{END_IF}"
        `shouldBe` Right ["2;", "4;"]
    it "ignores undefine of a name that is not defined" $
      kept "{undefine nothing}\nx;" `shouldBe` Right ["x;"]
    it "compare names without case" $
      kept "{define MyOpt}\n{IF defined(MYOPT)}x;{END_IF}\n{undefine myopt}\n{IF defined(MyOpt)}y;{END_IF}" `shouldBe` Right ["x;"]
    it "inside a region left out, do nothing" $
      kept "{define b}\n{IF defined(no)}\n{define a}\n{undefine b}\n{END_IF}\n{IF defined(a)}\nx;\n{END_IF}\n{IF defined(b)}\ny;\n{END_IF}" `shouldBe` Right ["y;"]
    it "last to the end of the object: a define of one function block is not seen by the next one" $ do
      let src =
            T.unlines
              [ "FUNCTION_BLOCK F1"
              , "{define d}"
              , "{IF defined(d)}in1;{END_IF}"
              , "END_FUNCTION_BLOCK"
              , "FUNCTION_BLOCK F2"
              , "{IF defined(d)}in2;{ELSE}out2;{END_IF}"
              , "END_FUNCTION_BLOCK"
              , "{IF defined(d)}top;{END_IF}"
              ]
      kept src `shouldBe` Right ["FUNCTION_BLOCK F1", "in1;", "END_FUNCTION_BLOCK", "FUNCTION_BLOCK F2", "out2;", "END_FUNCTION_BLOCK"]
    it "a define before an object's keyword belongs to that object; the methods of an FB share its defines" $ do
      let src =
            T.unlines
              [ "{define d}"
              , "FUNCTION_BLOCK F"
              , "METHOD M"
              , "{IF defined(d)}m;{END_IF}"
              , "END_METHOD"
              , "{IF defined(d)}f;{END_IF}"
              , "END_FUNCTION_BLOCK"
              , "PROGRAM MAIN"
              , "{IF defined(d)}p;{END_IF}"
              , "END_PROGRAM"
              ]
      kept src `shouldBe` Right ["FUNCTION_BLOCK F", "METHOD M", "m;", "END_METHOD", "f;", "END_FUNCTION_BLOCK", "PROGRAM MAIN", "END_PROGRAM"]
    it "a define in a GVL ends with its END_VAR; one in a TYPE block with END_TYPE" $ do
      kept "VAR_GLOBAL\n{define g}\nx : INT;\nEND_VAR\n{IF defined(g)}after;{END_IF}" `shouldBe` Right ["VAR_GLOBAL", "x : INT;", "END_VAR"]
      kept "TYPE\n{define t}\nT1 : INT;\nEND_TYPE\n{IF defined(t)}after;{END_IF}" `shouldBe` Right ["TYPE", "T1 : INT;", "END_TYPE"]
    it "an END_ keyword inside a region left out ends nothing" $
      kept "PROGRAM MAIN\n{define d}\n{IF defined(x)}\nEND_PROGRAM\n{END_IF}\n{IF defined(d)}still;{END_IF}\nEND_PROGRAM" `shouldBe` Right ["PROGRAM MAIN", "still;", "END_PROGRAM"]
    it "hasvalue compares the value, written quoted or not (NX-PRAGMA-15)" $ do
      kept "{define t '1'}\n{IF hasvalue(t, '1')}one;{ELSIF hasvalue(t, '2')}two;{END_IF}" `shouldBe` Right ["one;"]
      kept "{define t 2}\n{IF hasvalue(t, '1')}one;{ELSIF hasvalue(t, '2')}two;{END_IF}" `shouldBe` Right ["two;"]
      kept "{define t 'a b'}\n{IF hasvalue(t, 'a b')}ab;{END_IF}{IF hasvalue(t, 'A B')}AB;{END_IF}" `shouldBe` Right ["ab;"]
      kept "{define t}\n{IF hasvalue(t, '')}empty;{END_IF}{IF hasvalue(u, '')}u;{END_IF}" `shouldBe` Right ["empty;"]

  describe "operators (NX-PRAGMA-15)" $ do
    it "NOT binds tighter than AND, AND tighter than OR" $ do
      let with d c = holds d c
      with "{define a}" "NOT defined(b) AND defined(a)" `shouldBe` Right True
      with "{define a}" "NOT (defined(b) OR defined(a))" `shouldBe` Right False
      with "{define a}" "defined(a) OR defined(b) AND defined(c)" `shouldBe` Right True
      with "{define c}" "(defined(a) OR defined(b)) AND defined(c)" `shouldBe` Right False
      with "" "NOT NOT NOT defined(a)" `shouldBe` Right True
    it "defined(pou:...) is TRUE for programs, functions, function blocks, methods and actions of the text" $ do
      let decls = "FUNCTION F : INT\nEND_FUNCTION\nFUNCTION_BLOCK FB\nMETHOD M : INT\nEND_METHOD\nACTION Act:\nEND_ACTION\nEND_FUNCTION_BLOCK\nPROGRAM P\nVAR v : INT; END_VAR\nEND_PROGRAM"
      mapM (holds decls) ["defined(pou:F)", "defined(pou: fb)", "defined(pou:M)", "defined(pou:FB.M)", "defined(pou:Act)", "defined(pou:P)"] `shouldBe` Right (replicate 6 True)
      mapM (holds decls) ["defined(pou:v)", "defined(pou:Other)", "defined(pou:P.M)", "defined(F)"] `shouldBe` Right (replicate 4 False)
    it "defined(type:...) is TRUE for the names a TYPE block declares, not for their members" $ do
      let decls = "TYPE\n  S : STRUCT a : INT; b : ARRAY[1..2] OF INT; END_STRUCT;\n  E : (red, green := 2);\n  Al : INT := 5;\nEND_TYPE\nTYPE S2 EXTENDS S : STRUCT c : INT; END_STRUCT\nEND_TYPE\nFUNCTION_BLOCK FB\nEND_FUNCTION_BLOCK"
      mapM (holds decls) ["defined(type:S)", "defined(type:e)", "defined(type:Al)", "defined(type:S2)"] `shouldBe` Right (replicate 4 True)
      mapM (holds decls) ["defined(type:a)", "defined(type:c)", "defined(type:red)", "defined(type:INT)", "defined(type:FB)"] `shouldBe` Right (replicate 5 False)
    it "defined(variable:...) sees the variables of the POU it stands in and the GVLs, not those of other POUs" $ do
      let src =
            T.unlines
              [ "VAR_GLOBAL g : INT; END_VAR"
              , "FUNCTION_BLOCK Other"
              , "VAR_INPUT onlyThere : BOOL; END_VAR"
              , "END_FUNCTION_BLOCK"
              , "PROGRAM MAIN"
              , "VAR_INPUT i1, i2 : INT; END_VAR"
              , "VAR RETAIN r AT %MW0 : WORD; END_VAR"
              , "VAR_TEMP t : BOOL := TRUE; END_VAR"
              , "{IF defined(variable:i2) AND defined(variable:r) AND defined(variable:t) AND defined(variable:G)}all;{END_IF}"
              , "{IF defined(variable:onlyThere)}other;{END_IF}"
              , "{IF defined(variable:MAIN)}name;{END_IF}"
              , "END_PROGRAM"
              ]
      fmap (filter (`elem` ["all;", "other;", "name;"])) (kept src) `shouldBe` Right ["all;"]
    it "a method sees the variables of its function block, a derived FB those of its base" $ do
      let src =
            T.unlines
              [ "FUNCTION_BLOCK Base"
              , "VAR baseVar : INT; END_VAR"
              , "END_FUNCTION_BLOCK"
              , "FUNCTION_BLOCK Derived EXTENDS Base"
              , "VAR own : INT; END_VAR"
              , "METHOD M"
              , "VAR local : INT; END_VAR"
              , "{IF defined(variable:local) AND defined(variable:own) AND defined(variable:baseVar)}m;{END_IF}"
              , "END_METHOD"
              , "{IF defined(variable:local)}leak;{END_IF}"
              , "{IF defined(variable:baseVar)}d;{END_IF}"
              , "END_FUNCTION_BLOCK"
              ]
      fmap (filter (`elem` ["m;", "leak;", "d;"])) (kept src) `shouldBe` Right ["m;", "d;"]
    it "hasattribute(pou:...) reads the attributes written before the POU (NX-PRAGMA-5)" $ do
      let decls = "{attribute 'vision'}\n(* a comment between *)\n{attribute 'other' := 'x'}\nFUNCTION fun1 : INT\nEND_FUNCTION\nFUNCTION fun2 : INT\nEND_FUNCTION"
      mapM (holds decls) ["hasattribute(pou: fun1, 'vision')", "hasattribute(pou:fun1,'OTHER')", "NOT hasattribute(pou: fun2, 'vision')", "NOT hasattribute(pou: fun1, 'x')", "NOT hasattribute(pou:none, 'vision')"]
        `shouldBe` Right (replicate 5 True)
    it "hasattribute(variable:...) reads an attribute on the line before the declaration, or on its line (L3954-3955)" $ do
      let decls = "VAR_GLOBAL\n  {attribute 'DoCount'}\n  a, b : INT;\n  c : INT; {attribute 'same'}\n  {attribute 'displaymode':='hex'} {info 'x'}\n  (* a comment *)\n  d : DWORD;\n  {attribute 'first'} e : INT; f : INT;\nEND_VAR"
      mapM (holds decls) ["hasattribute(variable: a, 'DoCount')", "hasattribute(variable:b,'docount')", "hasattribute(variable:c, 'same')", "hasattribute(variable:d, 'displaymode')", "hasattribute(variable:e, 'first')", "hasattribute(variable:f, 'first')"]
        `shouldBe` Right (replicate 6 True)
      mapM (holds decls) ["hasattribute(variable:c, 'DoCount')", "hasattribute(variable:d, 'same')", "hasattribute(variable:d, 'x')", "hasattribute(variable:zz, 'DoCount')"] `shouldBe` Right (replicate 4 False)
    it "the variable a name means is the POU's own before a GVL's" $ do
      inMain "VAR_GLOBAL {attribute 'g'} v : LREAL; END_VAR" "v : INT;" "hastype(variable:v, INT) AND NOT hasattribute(variable:v, 'g')" `shouldBe` Right True
      inMain "VAR_GLOBAL {attribute 'g'} v : LREAL; END_VAR" "w : INT;" "hastype(variable:v, LREAL) AND hasattribute(variable:v, 'g')" `shouldBe` Right True
    it "hastype(variable:...) compares the declared type, or its ANY_ group (NX-TYPE-84, NX-TYPE-85)" $ do
      let vars = "i : INT; ul : ULINT; r : REAL; lr : LREAL; t : TIME; lt : LTIME; bo : BOOL; dw : DWORD; s : STRING(80); ws : WSTRING; d : DATE; tod : TOD; dt : DATE_AND_TIME; arr : ARRAY[1..3] OF INT; st : MyStruct; p : POINTER TO INT;"
          is v ty = inMain "" vars ("hastype(variable:" <> v <> ", " <> ty <> ")")
          table =
            [ ("i", "INT", True), ("i", "DINT", False), ("s", "STRING", True), ("lr", "LREAL", True), ("lr", "REAL", False)
            , ("tod", "TIME_OF_DAY", True), ("dt", "DT", True), ("st", "MyStruct", True)
            , ("i", "ANY_INT", True), ("ul", "ANY_INT", True), ("r", "ANY_INT", False)
            , ("r", "ANY_REAL", True), ("lr", "ANY_REAL", True), ("i", "ANY_REAL", False)
            , ("ul", "ANY_NUM", True), ("r", "ANY_NUM", True), ("t", "ANY_NUM", False)
            , ("t", "ANY_MAGNITUDE", True), ("lt", "ANY_MAGNITUDE", True), ("i", "ANY_MAGNITUDE", True), ("bo", "ANY_MAGNITUDE", False)
            , ("bo", "ANY_BIT", True), ("dw", "ANY_BIT", True), ("i", "ANY_BIT", False)
            , ("s", "ANY_STRING", True), ("ws", "ANY_STRING", True), ("bo", "ANY_STRING", False)
            , ("d", "ANY_DATE", True), ("tod", "ANY_DATE", True), ("dt", "ANY_DATE", True), ("t", "ANY_DATE", False)
            , ("ws", "ANY_ELEMENTARY", True), ("d", "ANY_ELEMENTARY", True), ("arr", "ANY_ELEMENTARY", False), ("st", "ANY_ELEMENTARY", False)
            , ("arr", "ANY_DERIVED", True), ("st", "ANY_DERIVED", True), ("p", "ANY_DERIVED", True), ("i", "ANY_DERIVED", False)
            , ("arr", "ANY", True), ("bo", "ANY", True), ("nothing", "ANY", False)
            ]
      [(v, ty, is v ty) | (v, ty, _) <- table] `shouldBe` [(v, ty, Right e) | (v, ty, e) <- table]

  describe "comments and strings (NX-LEX-14, NX-LEX-15, NX-LEX-17)" $ do
    it "hold no pragmas" $ do
      let src = "(* {IF defined(a)} *)\n// {ELSE}\nx := '{END_IF}';\ny := \"{IF}\";\n"
      preprocess src `shouldBe` Right src
    it "nest: a brace after an inner comment is still inside the outer one" $ do
      let src = "(* (* inner *) {IF defined(a)} *)\nx;"
      preprocess src `shouldBe` Right src
    it "under nested-comments = no, the first *) closes the comment" $
      preprocessWith NoNesting "(* (* inner *) {IF defined(a)} *)\nx;\n{END_IF}"
        `shouldBe` Right ("(* (* inner *) " <> b "{IF defined(a)} *)\nx;\n{END_IF}")
    it "a brace not closed on its line is no pragma (NX-PRAGMA-1)" $ do
      let src = "{IF defined(a)\n}\nx;"
      preprocess src `shouldBe` Right src
    it "a closing brace in quotes does not close the pragma" $
      kept "{define v 'a}b'}\n{IF hasvalue(v, 'a}b')}x;{END_IF}" `shouldBe` Right ["x;"]

  describe "errors (kind pragma-syntax)" $ do
    it "an IF without END_IF, at the innermost IF still open" $ do
      failure "x;\n{IF defined(a)}\ny;\n" `shouldBe` Just ("pragma-syntax", 2, 1)
      failure "{IF defined(a)}\n  {IF defined(b)}\n{END_IF}\n" `shouldBe` Just ("pragma-syntax", 1, 1)
      failure "{IF defined(a)}\n  {IF defined(b)}\n" `shouldBe` Just ("pragma-syntax", 2, 3)
    it "ELSE, ELSIF or END_IF without IF" $ do
      failure "x;\n  {ELSE}\n" `shouldBe` Just ("pragma-syntax", 2, 3)
      failure "{ELSIF defined(a)}" `shouldBe` Just ("pragma-syntax", 1, 1)
      failure "{IF defined(a)}{END_IF}\n{END_IF}" `shouldBe` Just ("pragma-syntax", 2, 1)
    it "ELSIF after ELSE, and a second ELSE" $ do
      failure "{IF defined(a)}\n{ELSE}\n{ELSIF defined(b)}\n{END_IF}" `shouldBe` Just ("pragma-syntax", 3, 1)
      failure "{IF defined(a)}\n{ELSE}\n{ELSE}\n{END_IF}" `shouldBe` Just ("pragma-syntax", 3, 1)
    it "a badly formed condition, at the word that does not fit" $ do
      failure "{IF defined(a) XOR defined(b)}{END_IF}" `shouldBe` Just ("pragma-syntax", 1, 16)
      failure "{IF}{END_IF}" `shouldBe` Just ("pragma-syntax", 1, 4)
      failure "{IF defined(a}{END_IF}" `shouldBe` Just ("pragma-syntax", 1, 14)
      failure "{IF defined(thing:a)}{END_IF}" `shouldBe` Just ("pragma-syntax", 1, 13)
      failure "{IF hastype(variable:a, INT}{END_IF}" `shouldBe` Just ("pragma-syntax", 1, 28)
      failure "{IF hasvalue(a, b)}{END_IF}" `shouldBe` Just ("pragma-syntax", 1, 17)
      failure "{IF hasattribute(type:a, 'x')}{END_IF}" `shouldBe` Just ("pragma-syntax", 1, 18)
      failure "{IF 1}{END_IF}" `shouldBe` Just ("pragma-syntax", 1, 5)
    it "a condition of an ELSIF is read even when an earlier section was taken" $
      failure "{define a}{IF defined(a)}{ELSIF ???}{END_IF}" `shouldBe` Just ("pragma-syntax", 1, 33)
    it "a define without a name, and words after ELSE, END_IF or an undefined name" $ do
      failure "{define}" `shouldBe` Just ("pragma-syntax", 1, 8)
      failure "{define 'x'}" `shouldBe` Just ("pragma-syntax", 1, 8)
      failure "{IF defined(a)}{ELSE x}{END_IF}" `shouldBe` Just ("pragma-syntax", 1, 21)
      failure "{IF defined(a)}{END_IF x}" `shouldBe` Just ("pragma-syntax", 1, 23)
      failure "{undefine a b}" `shouldBe` Just ("pragma-syntax", 1, 10)
