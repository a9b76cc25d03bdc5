-- | The grammar: precedence (MT-OP-16, MT-OP-17), statements (MT-STMT),
-- declarations and operands (MT-VAR, MT-ARR, MT-MAP), module structure
-- (MT-POU-1), error kinds and positions (MT-VERR-1..6), nesting limit.
module Syntax.ParserSpec (spec) where

import Data.Text (Text)
import qualified Data.Text as T
import Stref.Policy
import Stref.Syntax
import Stref.Syntax.Parser
import Stref.Types (BasicType (..))
import Stref.Verification
import Test.Hspec

expr :: Text -> Either VerificationError (Expr ())
expr t = (() <$) <$> parseExpression mastertoolXE t

stmts :: Text -> Either VerificationError [Stmt ()]
stmts t = map (() <$) <$> parseStatements mastertoolXE t

modl :: Text -> Either VerificationError (Module ())
modl t = (() <$) <$> parseModule mastertoolXE "t.st" t

kindPos :: Either VerificationError a -> Maybe (Text, Pos)
kindPos = either (\e -> Just (veKind e, vePos e)) (const Nothing)

sameAs :: Text -> Text -> Expectation
sameAs a b = do
  expr a `shouldSatisfy` either (const False) (const True)
  expr a `shouldBe` expr b

v :: Text -> Expr ()
v = EVar () . Ident

int :: Integer -> Expr ()
int n = ELit () (LInt n 10)

prog :: Text -> Text
prog body = "PROGRAM P\nVAR X, A, B : INT; END_VAR\n" <> body <> "\nEND_PROGRAM\n"

spec :: Spec
spec = do
  describe "precedence, Table 4-14 (MT-OP-16)" $ do
    it "NOT a AND b = (NOT a) AND b" $ "NOT a AND b" `sameAs` "(NOT a) AND b"
    it "a OR b AND c = a OR (b AND c)" $ "a OR b AND c" `sameAs` "a OR (b AND c)"
    it "a XOR b OR c = (a XOR b) OR c" $ "a XOR b OR c" `sameAs` "(a XOR b) OR c"
    it "a AND b XOR c = (a AND b) XOR c" $ "a AND b XOR c" `sameAs` "(a AND b) XOR c"
    it "a < b = c < d = (a < b) = (c < d)" $ "a < b = c < d" `sameAs` "(a < b) = (c < d)"
    it "a = b AND c = d = (a = b) AND (c = d)" $ "a = b AND c = d" `sameAs` "(a = b) AND (c = d)"
    it "-a * b = (-a) * b" $ "-a * b" `sameAs` "(-a) * b"
    it "a + b * c = a + (b * c)" $ "a + b * c" `sameAs` "a + (b * c)"
    it "a + b < c = (a + b) < c" $ "a + b < c" `sameAs` "(a + b) < c"
    it "a MOD b + c = (a MOD b) + c" $ "a MOD b + c" `sameAs` "(a MOD b) + c"
    it "& is AND (MT-OP-14)" $ "a & b OR c" `sameAs` "(a AND b) OR c"
    it "builds the tree of -a * b with the minus inside" $
      expr "-a * b" `shouldBe` Right (EBinary () Mul (EUnary () Neg (v "a")) (v "b"))
    it "reads a * -b with a unary minus on the right" $
      expr "a * -b" `shouldBe` Right (EBinary () Mul (v "a") (EUnary () Neg (v "b")))

  describe "associativity (MT-OP-17)" $ do
    it "10 - 4 - 3 = (10 - 4) - 3" $
      expr "10 - 4 - 3" `shouldBe` Right (EBinary () Sub (EBinary () Sub (int 10) (int 4)) (int 3))
    it "100 / 10 / 5 = (100 / 10) / 5" $
      expr "100 / 10 / 5" `shouldBe` Right (EBinary () Div (EBinary () Div (int 100) (int 10)) (int 5))
    it "a OR b OR c is left-nested" $ "a OR b OR c" `sameAs` "(a OR b) OR c"

  describe "operands of expressions" $ do
    it "reads calls with several arguments, indexing and nesting" $
      expr "F(a, V[i + 1], G(2))" `shouldBe` Right (ECall () (Ident "F") [v "a", EIndex () (Ident "V") (EBinary () Add (v "i") (int 1)), ECall () (Ident "G") [int 2]])
    it "reads EXPT as a call (MT-OP-20)" $
      expr "EXPT(base, expoente)" `shouldBe` Right (ECall () (Ident "EXPT") [v "base", v "expoente"])
    it "drops parentheses" $ expr "((a))" `shouldBe` Right (v "a")

  describe "statements (MT-STMT)" $ do
    it "reads assignment, indexed assignment and a call statement" $
      stmts "X := 1; V[2] := X; INSERIR_VALOR(HORA);"
        `shouldBe` Right
          [ Assign () (LVar () (Ident "X")) (int 1)
          , Assign () (LIndex () (Ident "V") (int 2)) (v "X")
          , CallStmt () (Ident "INSERIR_VALOR") [v "HORA"]
          ]
    it "reads IF with ELSIF and ELSE" $
      stmts "IF a THEN X := 1; ELSIF b THEN X := 2; ELSE X := 3; END_IF;"
        `shouldBe` Right [If () [(v "a", [Assign () (LVar () (Ident "X")) (int 1)]), (v "b", [Assign () (LVar () (Ident "X")) (int 2)])] (Just [Assign () (LVar () (Ident "X")) (int 3)])]
    it "reads ELSEIF as ELSIF under elsif-keyword=ELSIF+ELSEIF (A1)" $
      stmts "IF a THEN X := 1; ELSEIF b THEN X := 2; END_IF;"
        `shouldBe` stmts "IF a THEN X := 1; ELSIF b THEN X := 2; END_IF;"
    it "rejects ELSEIF under elsif-keyword=ELSIF" $ do
      let strict = mastertoolXE {pElsifKeyword = ElsifOnly}
      either (Just . veKind) (const Nothing) (parseStatements strict "IF a THEN X := 1; ELSEIF b THEN X := 2; END_IF;")
        `shouldBe` Just "expected-token"
      either (Just . veKind) (const Nothing) (parseStatements strict "IF a THEN X := 1; ELSIF b THEN X := 2; END_IF;")
        `shouldBe` Nothing
    it "reads CASE with lists, ranges, signed values, names and ELSE" $
      stmts "CASE t OF 0 : X := 10; 1, 2, 5..10 : X := 10; -3..-1, FIM : ; ELSE X := 0; END_CASE;"
        `shouldBe` Right
          [ Case
              ()
              (v "t")
              [ CaseArm () [LabelValue (int 0)] [Assign () (LVar () (Ident "X")) (int 10)]
              , CaseArm () [LabelValue (int 1), LabelValue (int 2), LabelRange (int 5) (int 10)] [Assign () (LVar () (Ident "X")) (int 10)]
              , CaseArm () [LabelRange (EUnary () Neg (int 3)) (EUnary () Neg (int 1)), LabelValue (v "FIM")] [Empty ()]
              ]
              (Just [Assign () (LVar () (Ident "X")) (int 0)])
          ]
    it "ends a CASE arm where a named label starts the next arm" $
      stmts "CASE t OF INI : X := 1; FIM : X := 2; END_CASE;"
        `shouldBe` Right [Case () (v "t") [CaseArm () [LabelValue (v "INI")] [Assign () (LVar () (Ident "X")) (int 1)], CaseArm () [LabelValue (v "FIM")] [Assign () (LVar () (Ident "X")) (int 2)]] Nothing]
    it "reads WHILE, REPEAT ... UNTIL ... END_REPEAT, FOR with and without BY, EXIT, RETURN and ;" $
      stmts "WHILE a DO EXIT; END_WHILE; REPEAT ; UNTIL b END_REPEAT; FOR I := 1 TO 10 BY 2 DO RETURN; END_FOR; FOR I := 1 TO 3 DO END_FOR;"
        `shouldBe` Right
          [ While () (v "a") [Exit ()]
          , Repeat () [Empty ()] (v "b")
          , For () ((), Ident "I") (int 1) (int 10) (Just (int 2)) [Return ()]
          , For () ((), Ident "I") (int 1) (int 3) Nothing []
          ]
    it "requires ; after END_IF (MT-STMT-23)" $
      kindPos (stmts "IF a THEN ; END_IF X := 1;") `shouldBe` Just ("expected-token", Pos 1 20)

  describe "declarations (MT-VAR, MT-ARR, MT-MAP)" $ do
    it "reads several names, CONSTANT, AT with bits and table positions, arrays and initialisers" $ do
      let src =
            T.unlines
              [ "VAR CONSTANT INI : INT := 1; END_VAR"
              , "PROGRAM P"
              , "VAR"
              , "  A, B : DINT;"
              , "  PRESSAO_ALTA AT %M0006.6 : BOOL;"
              , "  T AT %TM0010[ 0 ] : ARRAY[1..3] OF INT := [1, 2, 3];"
              , "  BAD AT %d0001 : INT;"
              , "END_VAR"
              , ";"
              , "END_PROGRAM"
              ]
      case modl src of
        Left e -> expectationFailure (show e)
        Right (Module [g] [] (Program () (Ident "P") [b] [Empty ()])) -> do
          vbConstant g `shouldBe` True
          map vdNames (vbDecls b) `shouldBe` [[((), Ident "A"), ((), Ident "B")], [((), Ident "PRESSAO_ALTA")], [((), Ident "T")], [((), Ident "BAD")]]
          map (fmap snd . vdAt) (vbDecls b)
            `shouldBe` [Nothing, Just (OperandRef "M" 6 (BitOf 6)), Just (OperandRef "TM" 10 (Position 0)), Just (OperandRef "D" 1 NoSub)]
          map vdType (vbDecls b) `shouldBe` [TBasic DINT, TBasic BOOL, TArray (int 1) (int 3) INT, TBasic INT]
          map vdInit (vbDecls b) `shouldBe` [Nothing, Nothing, Just (InitList () [int 1, int 2, int 3]), Nothing]
        Right other -> expectationFailure ("unexpected shape: " <> show other)
    it "refuses AT after several names" $
      kindPos (modl (prog' "A, B AT %M0001 : INT;")) `shouldBe` Just ("unexpected", Pos 2 10)
    it "refuses AT in VAR_INPUT" $
      fmap fst (kindPos (modl "PROGRAM P VAR_INPUT A AT %M0001 : INT; END_VAR ; END_PROGRAM")) `shouldBe` Just "unexpected"
    it "refuses a type MasterTool XE does not have, saying so" $ do
      let r = modl (prog' "S : STRING;")
      fmap fst (kindPos r) `shouldBe` Just "unsupported-type"
      either (T.isInfixOf "not supported by MasterTool XE" . veMessage) (const False) r `shouldBe` True
    it "reads operand spellings of the manual (MT-MAP-7)" $
      mapM_
        ( \(src, op) ->
            fmap (map (fmap snd . vdAt) . concatMap vbDecls . prBlocks . modProgram) (modl (prog' ("X AT " <> src <> " : INT;")))
              `shouldBe` Right [Just op]
        )
        [ ("%M200", OperandRef "M" 200 NoSub)
        , ("%M0123", OperandRef "M" 123 NoSub)
        , ("%F0", OperandRef "F" 0 NoSub)
        , ("%TM010[15]", OperandRef "TM" 10 (Position 15))
        , ("%TM0010[000]", OperandRef "TM" 10 (Position 0))
        , ("%E0010.5", OperandRef "E" 10 (BitOf 5))
        , ("%tm0011[ 0 ]", OperandRef "TM" 11 (Position 0))
        ]
    it "refuses malformed operands with invalid-operand" $
      mapM_
        (\src -> (src, fmap fst (kindPos (modl (prog' ("X AT " <> src <> " : INT;"))))) `shouldBe` (src, Just "invalid-operand"))
        ["%1234", "%M", "% M0001", "%TM0010[2].1"]
    it "refuses an operand without %" $
      fmap fst (kindPos (modl (prog' "X AT M0001 : INT;"))) `shouldBe` Just "expected-token"

  describe "module structure (MT-POU-1)" $ do
    it "reads globals, functions, then the program" $
      fmap (\m -> (length (modGlobals m), length (modFunctions m))) (modl "VAR G : INT; END_VAR FUNCTION F : INT VAR_INPUT A : INT; END_VAR F := A; END_FUNCTION PROGRAM P ; END_PROGRAM")
        `shouldBe` Right (1, 1)
    it "refuses a module without PROGRAM" $
      kindPos (modl "FUNCTION F : INT VAR_INPUT A : INT; END_VAR F := A; END_FUNCTION") `shouldBe` Just ("expected-token", Pos 1 65)
    it "refuses anything after END_PROGRAM" $
      kindPos (modl "PROGRAM P ; END_PROGRAM PROGRAM Q ; END_PROGRAM") `shouldBe` Just ("unexpected", Pos 1 25)
    it "refuses global variables after a function" $
      kindPos (modl "FUNCTION F : INT VAR_INPUT A : INT; END_VAR F := A; END_FUNCTION VAR G : INT; END_VAR PROGRAM P ; END_PROGRAM") `shouldBe` Just ("unexpected", Pos 1 66)
    it "refuses ; after END_PROGRAM (the manual never writes it)" $
      fmap fst (kindPos (modl "PROGRAM P ; END_PROGRAM;")) `shouldBe` Just "unexpected"

  describe "syntax errors (MT-VERR-4..6)" $ do
    it "IF ... END_WHILE: expected END_IF instead of END_WHILE (MT-VERR-4)" $ do
      let r = modl (prog "IF A = 1 THEN X := 1; END_WHILE;")
      kindPos r `shouldBe` Just ("expected-token", Pos 3 23)
      either veMessage (const "") r `shouldSatisfy` (\m -> "END_IF" `T.isInfixOf` m && "'END_WHILE'" `T.isInfixOf` m)
    it "X := 1 2: 2 not expected after 1 (MT-VERR-5)" $ do
      let r = modl (prog "X := 1 2;")
      kindPos r `shouldBe` Just ("unexpected-after", Pos 3 8)
      either veMessage (const "") r `shouldSatisfy` (\m -> "'2'" `T.isInfixOf` m && "'1'" `T.isInfixOf` m)
    it "a stray END_IF; is not expected (MT-VERR-6)" $
      kindPos (modl (prog "X := 1;\nEND_IF;")) `shouldBe` Just ("unexpected", Pos 4 1)
    it "names what was expected and what was found" $
      either veMessage (const "") (modl (prog "X = 1;")) `shouldSatisfy` (\m -> "':='" `T.isInfixOf` m && "'='" `T.isInfixOf` m)
    it "reports the end of the file" $
      either veMessage (const "") (modl "PROGRAM P X := 1;") `shouldSatisfy` T.isInfixOf "end of the file"
    it "counts a tab as one column" $
      kindPos (modl "PROGRAM P\n\tX := 1 2;\nEND_PROGRAM") `shouldBe` Just ("unexpected-after", Pos 2 9)

  describe "positions" $ do
    it "puts statements and operands at their first token and binary operations at the operator" $
      parseStatements mastertoolXE "  X := a +\n  -b;"
        `shouldBe` Right
          [ Assign
              (Pos 1 3)
              (LVar (Pos 1 3) (Ident "X"))
              (EBinary (Pos 1 10) Add (EVar (Pos 1 8) (Ident "a")) (EUnary (Pos 2 3) Neg (EVar (Pos 2 4) (Ident "b"))))
          ]

  describe "standard function names (MT-OP-21)" $ do
    it "may be called, as an expression or a statement" $ do
      fmap (map (() <$)) (parseStatements mastertoolXE "SQRT(2); X := MAX(1, 2);")
        `shouldBe` Right [CallStmt () (Ident "SQRT") [int 2], Assign () (LVar () (Ident "X")) (ECall () (Ident "MAX") [int 1, int 2])]
    it "may not be assigned or read as variables" $ do
      fmap fst (kindPos (stmts "ABS := 1;")) `shouldBe` Just "unexpected"
      fmap fst (kindPos (stmts "X := LIMIT + 1;")) `shouldBe` Just "unexpected"

  describe "nesting limit" $ do
    it "refuses 1000 nested parentheses with nesting-too-deep" $
      fmap fst (kindPos (expr (T.replicate 1000 "(" <> "1" <> T.replicate 1000 ")"))) `shouldBe` Just "nesting-too-deep"
    it "refuses 1000 nested IF statements with nesting-too-deep" $
      fmap fst (kindPos (stmts (T.replicate 1000 "IF a THEN " <> T.replicate 1000 "END_IF; "))) `shouldBe` Just "nesting-too-deep"
    it "accepts 100 nested parentheses" $
      expr (T.replicate 100 "(" <> "1" <> T.replicate 100 ")") `shouldBe` Right (int 1)
    it "accepts a long flat sum (left nesting is not depth)" $
      fmap (const ()) (expr (T.intercalate " + " (replicate 5000 "1"))) `shouldBe` Right ()
  where
    prog' decl = "PROGRAM P\nVAR " <> decl <> " END_VAR ; END_PROGRAM"
