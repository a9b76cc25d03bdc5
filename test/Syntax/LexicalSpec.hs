-- | The lexical tables of the manual (catalogue MT-LEX-6, MT-LEX-12,
-- MT-LEX-14, MT-LEX-15, MT-LEX-18), comments under both nesting policies,
-- keywords and reserved words. Expected values are the catalogue's.
module Syntax.LexicalSpec (spec) where

import Data.Ratio ((%))
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Policy
import Stref.Syntax
import Stref.Syntax.Parser
import Stref.Verification
import Test.Hspec

expr :: Text -> Either VerificationError (Expr ())
expr t = (() <$) <$> parseExpression mastertoolXE t

kind :: Either VerificationError a -> Maybe Text
kind = either (Just . veKind) (const Nothing)

-- | A program declaring one variable with the given name.
declaring :: Text -> Text
declaring n = "PROGRAM P VAR " <> n <> " : INT; END_VAR ; END_PROGRAM"

parsesModule :: Policies -> Text -> Either VerificationError (Module ())
parsesModule p t = (() <$) <$> parseModule p "t.st" t

lit :: Literal -> Either VerificationError (Expr ())
lit = Right . ELit ()

spec :: Spec
spec = do
  describe "Table 4-2 identifiers (MT-LEX-6)" $ do
    it "accepts the valid identifiers of both languages" $
      mapM_
        (\n -> expr n `shouldBe` Right (EVar () (Ident n)))
        ["EstadoBomba", "ALM_PresaoAlta", "B1_ATIVADA", "_1001_1", "testePressao", "PumpStatus", "ALM_PressureHigh", "B1_ACTIVE", "pressureTest"]
    it "accepts them as declared names" $
      mapM_ (\n -> kind (parsesModule mastertoolXE (declaring n)) `shouldBe` Nothing) ["EstadoBomba", "_1001_1"]
    it "rejects __Teste and Bomba__B3214 (two '_' in a row) as invalid symbols" $ do
      kind (parsesModule mastertoolXE (declaring "__Teste")) `shouldBe` Just "invalid-symbol"
      kind (parsesModule mastertoolXE (declaring "Bomba__B3214")) `shouldBe` Just "invalid-symbol"
      kind (expr "Bomba__B3214") `shouldBe` Just "invalid-symbol"
    it "rejects Pressao_ (final '_') as an invalid symbol" $ do
      kind (parsesModule mastertoolXE (declaring "Pressao_")) `shouldBe` Just "invalid-symbol"
      kind (expr "Pressao_") `shouldBe` Just "invalid-symbol"
    it "rejects 154_Ligar (starts with a digit) as an invalid symbol" $
      kind (parsesModule mastertoolXE (declaring "154_Ligar")) `shouldBe` Just "invalid-symbol"
    it "rejects Valvula-125201 as a name: '-' is not part of a name" $ do
      kind (parsesModule mastertoolXE (declaring "Valvula-125201")) `shouldBe` Just "expected-token"
      -- in an expression it is a subtraction
      expr "Valvula-125201" `shouldBe` Right (EBinary () Sub (EVar () (Ident "Valvula")) (ELit () (LInt 125201 10)))

  describe "Table 4-3 integer literals (MT-LEX-10..12)" $ do
    it "reads the decimal examples" $ do
      expr "12547" `shouldBe` lit (LInt 12547 10)
      expr "10_531" `shouldBe` lit (LInt 10531 10)
      expr "6978" `shouldBe` lit (LInt 6978 10)
    it "reads -1_532 as minus applied to 1532 (MT-LEX-19)" $
      expr "-1_532" `shouldBe` Right (EUnary () Neg (ELit () (LInt 1532 10)))
    it "reads the based examples with their values" $ do
      expr "2#0000_1001" `shouldBe` lit (LInt 9 2)
      expr "2#01001100" `shouldBe` lit (LInt 76 2)
      expr "2#001" `shouldBe` lit (LInt 1 2)
      expr "8#457" `shouldBe` lit (LInt 303 8) -- 4*64 + 5*8 + 7
      expr "8#6254" `shouldBe` lit (LInt 3244 8) -- 6*512 + 2*64 + 5*8 + 4
      expr "16#4576_ab4f" `shouldBe` lit (LInt 1165405007 16)
      expr "16#980ABE4D" `shouldBe` lit (LInt 2550840909 16)
      expr "16#FFFF_ffff" `shouldBe` lit (LInt 4294967295 16)
    it "reads the examples of MT-LEX-10" $ do
      expr "2#1111_1111" `shouldBe` lit (LInt 255 2)
      expr "16#00AA" `shouldBe` lit (LInt 170 16)
      expr "16#8000" `shouldBe` lit (LInt 32768 16)
    it "rejects #0010001 (no base): '#' cannot start a token" $
      kind (expr "#0010001") `shouldBe` Just "invalid-char"
    it "reads _1546 as a name, not a literal (MT-LEX-18)" $
      expr "_1546" `shouldBe` Right (EVar () (Ident "_1546"))
    it "reads -_5447 as minus applied to the name _5447 (MT-LEX-18)" $
      expr "-_5447" `shouldBe` Right (EUnary () Neg (EVar () (Ident "_5447")))
    it "rejects the invalid literals as invalid symbols" $
      mapM_
        (\t -> (t, kind (expr t)) `shouldBe` (t, Just "invalid-symbol"))
        ["4578_", "10__135", "2#4577_0158#00159", "16#_1789", "16#4587_", "2#102", "8#9", "3#12", "16#"]

  describe "Table 4-4 real literals (MT-LEX-13, MT-LEX-14)" $ do
    it "reads -1.34E-2 as minus applied to 0.0134" $
      expr "-1.34E-2" `shouldBe` Right (EUnary () Neg (ELit () (LReal (134 % 10000))))
    it "reads 1.0e+6, 1.234E6 and 1_254.4879 exactly" $ do
      expr "1.0e+6" `shouldBe` lit (LReal 1000000)
      expr "1.234E6" `shouldBe` lit (LReal 1234000)
      expr "1_254.4879" `shouldBe` lit (LReal (12544879 % 10000))
    it "rejects 1.34E-2.10 and 1.0E as invalid symbols" $ do
      kind (expr "1.34E-2.10") `shouldBe` Just "invalid-symbol"
      kind (expr "1.0E") `shouldBe` Just "invalid-symbol"
      kind (expr "1.0E+") `shouldBe` Just "invalid-symbol"
    it "does not read e +6 as a literal: it is the name e plus 6" $
      expr "e +6" `shouldBe` Right (EBinary () Add (EVar () (Ident "e")) (ELit () (LInt 6 10)))
    it "rejects _254.4879: a name followed by '.'" $
      kind (expr "_254.4879") `shouldBe` Just "expected-token"
    it "does not read 1. or .5 as reals" $ do
      kind (expr "1.") `shouldBe` Just "expected-token"
      kind (expr ".5") `shouldBe` Just "expected-token"
    it "reads 1..10 in an array bound as two integers" $
      kind (parsesModule mastertoolXE "PROGRAM P VAR V : ARRAY[1..10] OF INT; END_VAR ; END_PROGRAM") `shouldBe` Nothing

  describe "boolean constants (MT-LEX-16)" $ do
    it "reads TRUE and FALSE in any case" $ do
      expr "TRUE" `shouldBe` lit (LBool True)
      expr "false" `shouldBe` lit (LBool False)
      expr "True" `shouldBe` lit (LBool True)

  describe "characters (MT-LEX-15)" $ do
    it "rejects a character outside the language as invalid-char, at its position" $ do
      let r = parseStatements mastertoolXE "X := 1 $ 2;"
      kind r `shouldBe` Just "invalid-char"
      vePos <$> either Just (const Nothing) r `shouldBe` Just (Pos 1 8)
    it "rejects @ and a double quote" $ do
      kind (expr "a @ b") `shouldBe` Just "invalid-char"
      kind (expr "\"x\"") `shouldBe` Just "invalid-char"
    it "takes CR LF line ends and a byte-order mark as white space" $
      kind (parsesModule mastertoolXE "\xFEFFPROGRAM P\r\nVAR X : INT; END_VAR\r\nX := 1;\r\nEND_PROGRAM\r\n") `shouldBe` Nothing
    it "allows any character inside a comment" $
      expr "(* ação $ @ *) 5" `shouldBe` lit (LInt 5 10)

  describe "comments (MT-LEX-8)" $ do
    let noNest = mastertoolXE {pNestedComments = NoNesting}
        nest = mastertoolXE {pNestedComments = Nesting}
        stmts p t = fmap (map (() <$)) (parseStatements p t)
        assignX = [Assign () (LVar () (Ident "X")) (ELit () (LInt 1 10))]
    it "spans lines" $
      stmts noNest "(* one\ntwo *) X := 1;" `shouldBe` Right assignX
    it "without nesting, the first *) closes the comment" $ do
      stmts noNest "(* a (* b *) X := 1;" `shouldBe` Right assignX
      kind (stmts noNest "(* a (* b *) c *) X := 1;") `shouldBe` Just "expected-token"
    it "with nesting, each (* needs its own *)" $ do
      stmts nest "(* a (* b *) c *) X := 1;" `shouldBe` Right assignX
      kind (stmts nest "(* a (* b *) X := 1;") `shouldBe` Just "comment-not-closed"
    it "reports an unclosed comment at its start (MT-VERR-3)" $ do
      let r = parseModule mastertoolXE "t.st" "PROGRAM P\n; END_PROGRAM\n  (* open\n"
      kind r `shouldBe` Just "comment-not-closed"
      either (Just . vePos) (const Nothing) r `shouldBe` Just (Pos 3 3)

  describe "keywords and reserved words (MT-LEX-5, MT-LEX-17)" $ do
    it "reads keywords in any case" $
      kind (parsesModule mastertoolXE "program p var x : int; end_var if x = 1 then x := 2; end_if; end_program") `shouldBe` Nothing
    it "refuses a keyword as a declared name" $
      kind (parsesModule mastertoolXE (declaring "WHILE")) `shouldBe` Just "expected-token"
    it "refuses standard function names, predeclared names and INTERNAL_ names as declared names" $
      mapM_ (\n -> (n, kind (parsesModule mastertoolXE (declaring n))) `shouldBe` (n, Just "unexpected")) ["ABS", "sqrt", "INPUT1", "INTERNAL_X", "SINT"]
    it "reads a standard function name as a call (the checker reports it undeclared)" $
      expr "ABS(x)" `shouldBe` Right (ECall () (Ident "ABS") [EVar () (Ident "x")])
    it "reads conversion names as ordinary calls" $ do
      expr "INT_TO_REAL(x)" `shouldBe` Right (ECall () (Ident "INT_TO_REAL") [EVar () (Ident "x")])
      expr "ANY_TO_DINT(x)" `shouldBe` Right (ECall () (Ident "ANY_TO_DINT") [EVar () (Ident "x")])
    it "reads INTERNAL_OVERFLOW and the module signals as variables" $ do
      expr "INTERNAL_OVERFLOW" `shouldBe` Right (EVar () (Ident "INTERNAL_OVERFLOW"))
      expr "INPUT2" `shouldBe` Right (EVar () (Ident "INPUT2"))
    it "does not reserve END (decision A30)" $
      kind (parsesModule mastertoolXE (declaring "END")) `shouldBe` Nothing
    it "keeps the letters of a name as written" $
      expr "Nivel_Vaso1" `shouldBe` Right (EVar () (Ident (T.pack "Nivel_Vaso1")))
